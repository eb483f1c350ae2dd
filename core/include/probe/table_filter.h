// Pass 2 with a tap table (Manson & Sloan): each output texel sums 3 frames x N taps, read
// trilinearly from the pyramid, as docs/design.md "Tap tables" says. The CPU model that the optimizer
// fits and the GPU shader must match.
#pragma once

#include <vector>

#include "probe/tap_sum.h"
#include "probe/tap_table.h"

namespace probe {

// The taps of the output texel with cube vector d (faceUvToCubePoint of the texel centre, major
// component 1) at output level m: the first `used` taps of each frame (tapsInUse(table, m): a mix's
// padding is not evaluated), frames with weight <= 0 skipped, tap weights including the frame
// weight. Clears `taps` first.
void tableTaps(const TapTable& table, int level, int used, const glm::dvec3& cubeVector, std::vector<Tap>& taps);

// The table's taps as a TapGenerator (levels with alpha = 0 are copies): what the fit measures.
TapGenerator tableTapGenerator(const TapTable& table);
// Per output level, the FIS samples (fisSamples, bias 0, at the level's alpha) of a level handed to
// FIS (TableLevel::fisSamples); empty at the levels the table's taps filter.
std::vector<std::vector<Tap>> handOffSamples(const TapTable& table);
// The table method as the runtime filters with it: the table's taps, and at the levels handed to FIS
// (TableLevel::fisSamples) FIS's samples, bias 0, read from the same pyramid.
TapGenerator tableMethodTapGenerator(const TapTable& table);

// Filters a probe: builds the table's pyramid and computes every output level.
CubeLevels tableFilter(const CubeImage& source, const TapTable& table);
CubeLevels tableFilter(const CubeLevels& pyramid, const TapTable& table);

// Impulse response of one output texel of level m: weights over base texels (operators from
// pyramidOperators(table.faceSize, table.pyramid)).
std::vector<double> tableImpulseResponse(const TapTable& table, const std::vector<DownsampleOperator>& operators, int level,
                                         const Texel& texel);

} // namespace probe
