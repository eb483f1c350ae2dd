#include "checker_term.h"

#include <cmath>
#include <cstddef>

namespace probefit {

CheckerTerm prepareCheckerTerm(const std::vector<OutputTexel>& texels, const MomentBasis& basis, double weight) {
    CheckerTerm term{basis, std::vector<std::array<double, kMomentCount>>(texels.size()), weight};
#pragma omp parallel for schedule(dynamic, 4)
    for (std::size_t n = 0; n < texels.size(); ++n) term.reference[n] = kernelMoments(texels[n], basis);
    return term;
}

double checkerError(const ImpulseModel& model, const double* const* blocks, const OutputTexel& texel,
                    const std::array<double, kMomentCount>& reference, const MomentBasis& basis, double* gradient) {
    std::array<double, kMomentCount> m, slope;
    model.moments(blocks, texel, basis, m.data());
    double c = 0.0;
    for (int j = 0; j < kMomentCount; ++j) {
        const double d = m[j] - reference[j];
        c += std::abs(d);
        slope[j] = d > 0.0 ? 1.0 : (d < 0.0 ? -1.0 : 0.0);
    }
    if (gradient) model.moments(blocks, texel, basis, nullptr, slope.data(), gradient);
    return c;
}

double meanCheckerError(const ImpulseModel& model, const double* const* blocks, const std::vector<OutputTexel>& texels,
                        const CheckerTerm& term) {
    std::vector<double> c(texels.size());
#pragma omp parallel for schedule(dynamic, 4)
    for (std::size_t n = 0; n < texels.size(); ++n) c[n] = checkerError(model, blocks, texels[n], term.reference[n], term.basis, nullptr);
    double sum = 0.0, total = 0.0;
    for (std::size_t n = 0; n < texels.size(); ++n) {
        sum += texels[n].weight * c[n];
        total += texels[n].weight;
    }
    return total > 0.0 ? sum / total : 0.0;
}

} // namespace probefit
