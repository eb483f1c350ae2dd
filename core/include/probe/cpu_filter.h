// The methods filtered on the CPU with the shared model (probetools): what the GPU passes are tested
// against and the optimizer and the bench measure. The runtime needs none of it.
#pragma once

#include <vector>

#include "probe/cube_image.h"
#include "probe/filter_method.h"
#include "probe/fis.h"
#include "probe/pyramid.h"
#include "probe/roughness.h"
#include "probe/tap_sum.h"

namespace probe {

// The taps of every output level (empty for the reference, which reads no pyramid). A table's
// generator refers to method.table. FIS on a paraboloid map has the cube's taps: the same samples,
// which the map reads at its own levels (probe/paraboloid.h).
TapGenerator methodTapGenerator(const FilterMethod& method, int faceSize, int levelCount, const RoughnessMapping& mapping);

// Filters a probe on the CPU with the shared model: the reference, pass 1 and the method's taps, or
// FIS on a paraboloid map (paraboloidFilter).
CubeLevels filterOnCpu(const CubeImage& source, int levelCount, const RoughnessMapping& mapping, const FilterMethod& method);

// FIS alone: builds the pyramid of settings.pyramid and computes every output level.
CubeLevels fisFilter(const CubeImage& source, int levelCount, const RoughnessMapping& mapping, const FisSettings& settings);

// FIS's impulse response of one output texel of level m over base texels.
std::vector<double> fisImpulseResponse(const std::vector<DownsampleOperator>& operators, int faceSize, int levelCount,
                                       const RoughnessMapping& mapping, const FisSettings& settings, int level, const Texel& texel);

} // namespace probe
