#include "dense_passes.h"

#include <algorithm>
#include <cmath>

namespace probefit {

using namespace probe;

DensePasses::DensePasses(const std::vector<DownsampleOperator>& operators) {
    if (operators.empty()) return;
    const DownsampleOperator& op = operators[0];
    const std::size_t baseCount = texelCount(op.fineSize);
    parentStart_.assign(baseCount + 1, 0);
    for (const TexelWeight& e : op.entries) ++parentStart_[e.index + 1];
    for (std::size_t t = 0; t < baseCount; ++t) parentStart_[t + 1] += parentStart_[t];
    rowStart_ = op.rowStart;
    for (const TexelWeight& e : op.entries) {
        rowIndex_.push_back(e.index);
        rowWeight_.push_back(e.weight);
    }
    parentRow_.resize(op.entries.size());
    parentWeight_.resize(op.entries.size());
    std::vector<std::uint32_t> next(parentStart_.begin(), parentStart_.end() - 1);
    for (std::uint32_t r = 0; r + 1 < op.rowStart.size(); ++r)
        for (std::uint32_t e = op.rowStart[r]; e < op.rowStart[r + 1]; ++e) {
            const std::uint32_t slot = next[op.entries[e].index]++;
            parentRow_[slot] = r;
            parentWeight_[slot] = op.entries[e].weight;
        }
}

double DensePasses::measure(const std::vector<DownsampleOperator>& operators, std::vector<std::vector<double>>& weights, int top,
                            const std::vector<float>& kernel, const TailTerm& tail, std::vector<std::vector<double>>* adjoint,
                            double* tailError) const {
    for (int k = top; k > 1; --k) operators[k - 1].applyTranspose(weights[k], weights[k - 1]);
    std::vector<double>& base = weights[0];
    const double* coarse = top >= 1 ? weights[1].data() : nullptr;
    double* slope = adjoint ? (*adjoint)[0].data() : nullptr;
    double sum = 0.0, tailMass = 0.0;
    for (std::size_t t = 0; t < base.size(); ++t) {
        double w = base[t];
        base[t] = 0.0;
        // The transposed operator skips rows whose weight is zero; adding their products (zero)
        // changes at most the sign of a zero w, which neither |w - k| nor the slope sees.
        if (coarse)
            for (std::uint32_t n = parentStart_[t]; n < parentStart_[t + 1]; ++n) w += parentWeight_[n] * coarse[parentRow_[n]];
        const double d = w - static_cast<double>(kernel[t]);
        sum += std::abs(d);
        if (tail.contains(t)) tailMass += w;
        if (slope) slope[t] = d > 0.0 ? 1.0 : (d < 0.0 ? -1.0 : 0.0);
    }
    *tailError = std::abs(tailMass - tail.kernelMass);
    if (slope && tail.weight > 0.0) {
        const double step = tail.slope(tailMass);
        for (std::size_t t = 0; t < base.size(); ++t)
            if (tail.contains(t)) slope[t] += step;
    }
    if (adjoint && top >= 1) {
        // The first pull-up step as DownsampleOperator::apply, from the rows' indices and weights held apart.
        const double* fine = (*adjoint)[0].data();
        double* coarseAdjoint = (*adjoint)[1].data();
        for (std::size_t r = 0; r + 1 < rowStart_.size(); ++r) {
            double rowSum = 0.0;
            for (std::uint32_t e = rowStart_[r]; e < rowStart_[r + 1]; ++e) rowSum += rowWeight_[e] * fine[rowIndex_[e]];
            coarseAdjoint[r] = rowSum;
        }
        for (int k = 2; k <= top; ++k) operators[k - 1].apply((*adjoint)[k - 1], (*adjoint)[k]);
    }
    for (int k = 1; k <= top; ++k) std::fill(weights[k].begin(), weights[k].end(), 0.0);
    return sum;
}

} // namespace probefit
