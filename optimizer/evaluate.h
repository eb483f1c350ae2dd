// The analyzer beside the optimizer: a table's impulse-response L1 per level over all output
// texels or the stratified set, and its smallest weight sum.
#pragma once

#include <functional>
#include <vector>

#include "impulse_model.h"

namespace probefit {

struct LevelEvaluation {
    probe::ImpulseError error; // solid-angle (stratum) weighted mean, worst texel
    double minWeightSum = 0.0;
    double tailMean = 0.0; // the weighted mean of the tail term's |W - K| (impulse_model.h)
};

enum class TexelSet { all, stratified };

// The texels a level is measured on (the stratified set with the table's budget).
std::vector<probe::WeightedTexel> levelTexels(const probe::TapTable& table, int level, TexelSet set);

// One level (alpha = 0 levels are copies, error 0), all cores. Each texel's kernel is read only
// where its taps reach; its normalization, a pass over every base texel, is shared by the texels
// that a symmetry of the cube maps onto each other (about 48 each).
LevelEvaluation evaluateLevel(const probe::TapTable& table, int level, TexelSet set);

// The number of those classes among all texels of a level of face size `size`.
std::size_t symmetryClassCount(int size);

// The texels of level `level` measured exactly: each with its reference lobe over every base texel
// (probe::ReferenceLobe over `geometry`, the base's, which must outlive them), whose normalization is
// computed once per class of symmetric texels.
std::vector<OutputTexel> measuredTexels(const probe::CubeGeometry& geometry, int level, const probe::LevelLobe& lobe,
                                        const std::vector<probe::WeightedTexel>& texels);

// The same from prepared texels and coefficient blocks (what the fit uses).
LevelEvaluation evaluatePrepared(const ImpulseModel& model, const double* const* blocks, const std::vector<OutputTexel>& texels);

// Records an evaluation of `set` in a level: its L1 as that set's record, and its smallest weight sum
// (the lower of both sets' where the other set is recorded too).
void recordEvaluation(probe::TableLevel& level, TexelSet set, const LevelEvaluation& evaluation);

// Measures a level's stratified record (and its smallest weight sum) again on the table's own budget:
// for a level taken from a table fitted on another (`probefit select`, `probefit mix`), so that the
// record is what `probefit eval` finds. The all-texel record does not depend on the budget.
void restratifyLevel(probe::TapTable& table, int level);

} // namespace probefit
