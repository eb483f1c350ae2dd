// The fit's checker term. A few taps that read pyramid levels where sharp, high-frequency content is
// still resolved alias it: their sum turns a checkerboard into noise that the exact filter, whose
// lobe averages it away, does not have (the filtered checkerboard of a rough level is nearly flat).
// The impulse L1 bounds that error but does not see it, as it is the part of the response's error
// that does not cancel on such content. The term measures it per output texel:
//   c = sum_j |m_j - r_j|,
// m the response's moments of the checkerboards of MomentBasis (MomentFunctions::checkers), r the
// reference's.
#pragma once

#include <array>
#include <vector>

#include "impulse_model.h"

namespace probefit {

struct CheckerTerm {
    const MomentBasis& basis;                                // MomentFunctions::checkers
    std::vector<std::array<double, kMomentCount>> reference; // r per texel of the level, in order
    double weight = 0.0;
};

// The term for these texels (with kernels), r computed once, all cores.
CheckerTerm prepareCheckerTerm(const std::vector<OutputTexel>& texels, const MomentBasis& basis, double weight);

// c of texel n; with `gradient` (blockCount * blockSize values, overwritten) also d c / d coefficient.
double checkerError(const ImpulseModel& model, const double* const* blocks, const OutputTexel& texel,
                    const std::array<double, kMomentCount>& reference, const MomentBasis& basis, double* gradient);

// The weighted mean of c over the texels.
double meanCheckerError(const ImpulseModel& model, const double* const* blocks, const std::vector<OutputTexel>& texels,
                        const CheckerTerm& term);

} // namespace probefit
