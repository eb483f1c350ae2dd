#include "dense_passes.h"

#include <algorithm>
#include <cmath>

namespace probefit {

using namespace probe;

namespace {

// sum + weight[0] * values[index[0]] + ... over `count` slots, added in order; Slots > 0 fixes the
// count at compile time.
template <int Slots>
double addSlots(double sum, const std::uint32_t* index, const double* weight, const double* values, int count) {
    if constexpr (Slots > 0) count = Slots;
    for (int n = 0; n < count; ++n) sum += weight[n] * values[index[n]];
    return sum;
}

// The kernel the L1 is measured against: its values in floats (the fit's texels, which hold every
// one), or a lobe evaluated in the pass (measured texels: no vector of the whole cube to fill).
struct KernelValues {
    const float* values;
    double operator()(std::size_t t) const { return static_cast<double>(values[t]); }
};
struct KernelLobe {
    const ReferenceLobe& lobe;
    double operator()(std::size_t t) const { return lobe(t); }
};

} // namespace

DensePasses::DensePasses(const std::vector<DownsampleOperator>& operators) {
    if (operators.empty()) return;
    const DownsampleOperator& op = operators[0];
    const std::size_t baseCount = texelCount(op.fineSize), rowCount = op.rowStart.size() - 1;
    std::vector<int> parents(baseCount, 0);
    for (const TexelWeight& e : op.entries) parentSlots_ = std::max(parentSlots_, ++parents[e.index]);
    for (std::size_t r = 0; r < rowCount; ++r) rowSlots_ = std::max(rowSlots_, static_cast<int>(op.rowStart[r + 1] - op.rowStart[r]));
    parentRow_.assign(baseCount * parentSlots_, 0);
    parentWeight_.assign(parentRow_.size(), 0.0);
    rowIndex_.assign(rowCount * rowSlots_, 0);
    rowWeight_.assign(rowIndex_.size(), 0.0);
    std::fill(parents.begin(), parents.end(), 0);
    for (std::uint32_t r = 0; r < rowCount; ++r)
        for (std::uint32_t e = op.rowStart[r]; e < op.rowStart[r + 1]; ++e) {
            const TexelWeight& entry = op.entries[e];
            const std::size_t parent = entry.index * static_cast<std::size_t>(parentSlots_) + parents[entry.index]++;
            parentRow_[parent] = r;
            parentWeight_[parent] = entry.weight;
            const std::size_t slot = r * static_cast<std::size_t>(rowSlots_) + (e - op.rowStart[r]);
            rowIndex_[slot] = entry.index;
            rowWeight_[slot] = entry.weight;
        }
}

double DensePasses::measure(const std::vector<DownsampleOperator>& operators, std::vector<std::vector<double>>& weights, int top,
                            const std::vector<float>& kernel, const TailTerm& tail, std::vector<std::vector<double>>* adjoint,
                            double* tailError) const {
    const KernelValues values{kernel.data()};
    if (parentSlots_ == 4 && rowSlots_ == 16) return measureWith<4, 16>(operators, weights, top, values, tail, adjoint, tailError);
    if (parentSlots_ == 1 && rowSlots_ == 4) return measureWith<1, 4>(operators, weights, top, values, tail, adjoint, tailError);
    return measureWith<0, 0>(operators, weights, top, values, tail, adjoint, tailError);
}

double DensePasses::measure(const std::vector<DownsampleOperator>& operators, std::vector<std::vector<double>>& weights, int top,
                            const ReferenceLobe& lobe) const {
    const KernelLobe kernel{lobe};
    double tailError = 0.0;
    if (parentSlots_ == 4 && rowSlots_ == 16) return measureWith<4, 16>(operators, weights, top, kernel, {}, nullptr, &tailError);
    if (parentSlots_ == 1 && rowSlots_ == 4) return measureWith<1, 4>(operators, weights, top, kernel, {}, nullptr, &tailError);
    return measureWith<0, 0>(operators, weights, top, kernel, {}, nullptr, &tailError);
}

template <int ParentSlots, int RowSlots, typename Kernel>
double DensePasses::measureWith(const std::vector<DownsampleOperator>& operators, std::vector<std::vector<double>>& weights, int top,
                                const Kernel& kernel, const TailTerm& tail, std::vector<std::vector<double>>* adjoint,
                                double* tailError) const {
    for (int k = top; k > 1; --k) operators[k - 1].applyTranspose(weights[k], weights[k - 1]);
    std::vector<double>& base = weights[0];
    const double* coarse = top >= 1 ? weights[1].data() : nullptr;
    double* slope = adjoint ? (*adjoint)[0].data() : nullptr;
    double sum = 0.0, tailMass = 0.0;
    for (std::size_t t = 0; t < base.size(); ++t) {
        double w = base[t];
        base[t] = 0.0;
        // The transposed operator skips rows whose weight is zero, and the padded slots add zeros:
        // either changes at most the sign of a zero w, which neither |w - k| nor the slope sees.
        if (coarse) {
            const std::size_t first = t * static_cast<std::size_t>(parentSlots_);
            w = addSlots<ParentSlots>(w, &parentRow_[first], &parentWeight_[first], coarse, parentSlots_);
        }
        const double d = w - kernel(t);
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
        // The first pull-up step as DownsampleOperator::apply, from the padded rows.
        const double* fine = (*adjoint)[0].data();
        std::vector<double>& coarseAdjoint = (*adjoint)[1];
        for (std::size_t r = 0; r < coarseAdjoint.size(); ++r) {
            const std::size_t first = r * static_cast<std::size_t>(rowSlots_);
            coarseAdjoint[r] = addSlots<RowSlots>(0.0, &rowIndex_[first], &rowWeight_[first], fine, rowSlots_);
        }
        for (int k = 2; k <= top; ++k) operators[k - 1].apply((*adjoint)[k - 1], (*adjoint)[k]);
    }
    for (int k = 1; k <= top; ++k) std::fill(weights[k].begin(), weights[k].end(), 0.0);
    return sum;
}

} // namespace probefit
