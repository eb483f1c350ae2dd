// The fit's seam term. Across a face edge, the step of the output between two neighbouring texels
// should be the exact filter's step; a table whose taps bend at the edge (theta and phi are
// continuous there, not smooth) makes it steeper, most visibly on smooth content. Smooth content is
// carried by the low-order moments of the response, so the term compares how they change across the
// edge: s = sum_j |(m_j(a) - m_j(b)) - (r_j(a) - r_j(b))|, m the table's moments, r the reference's.
#pragma once

#include <array>
#include <vector>

#include "impulse_model.h"

namespace probefit {

struct SeamPair {
    OutputTexel a, b;                                 // neighbours across a face edge (their kernels dropped: only moments are compared)
    std::array<double, kMomentCount> referenceStep{}; // r(a) - r(b)
};

// At most `budget` pairs of neighbouring texels across the face edges of output level m (every edge,
// evenly in texel order), all cores.
std::vector<SeamPair> prepareSeamPairs(int faceSize, int level, const probe::LevelLobe& lobe, int budget, const MomentBasis& basis);

// s of one pair; with `gradient` (blockCount * blockSize values, overwritten) also d s / d coefficient,
// using `scratch` (resized as needed).
double seamError(const ImpulseModel& model, const double* const* blocks, const SeamPair& pair, const MomentBasis& basis, double* gradient,
                 std::vector<double>& scratch);

} // namespace probefit
