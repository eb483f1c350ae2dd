// The impulse model's dense passes, where the taps reach much of the cube: weights on pyramid
// texels pushed back to the base, the L1 against the reference kernel with its slope sign(w - k),
// and the slope pulled back up the pyramid. The last push-back step (level 1 to the base, 3/4 of
// the work) runs as a gather over each base texel's parents, fused with the L1: the base weights
// are never stored. Each parent is added in the order the transposed operator adds it, so the
// sums are bit for bit those of probe::pushBackToBase followed by a separate L1 pass.
#pragma once

#include <cstdint>
#include <vector>

#include "probe/pyramid.h"
#include "probe/reference.h"

namespace probefit {

// The tail term beside the L1 (impulse_model.h): the base texels of the lobe's tail (a bit each;
// none without a mask), the reference's mass there, and the term's weight in the slope (0: the
// L1's slope alone).
struct TailTerm {
    const std::uint64_t* mask = nullptr;
    double kernelMass = 0.0;
    double weight = 0.0;
    bool contains(std::size_t t) const { return mask && ((mask[t / 64] >> (t % 64)) & 1u); }
    // d(weight |W - K|) / dW at the response's tail mass W: what the term adds to each tail texel's slope.
    double slope(double mass) const { return mass > kernelMass ? weight : (mass < kernelMass ? -weight : 0.0); }
};

class DensePasses {
public:
    // The passes over the pyramid of these operators (probe::pyramidOperators), which measure() takes again.
    explicit DensePasses(const std::vector<probe::DownsampleOperator>& operators);

    // weights: per pyramid level (zero above `top`), the taps' weights; left all zero on return.
    // Returns sum_t |w_t - k_t| over the base texels t of the pushed-back weights w, and |W - K| of the
    // tail into *tailError. With `adjoint` (per level, sized like weights), also d(L1 + tail.weight
    // |W - K|) / d(weight on pyramid texel p) into adjoint[k][p] for k <= top.
    double measure(const std::vector<probe::DownsampleOperator>& operators, std::vector<std::vector<double>>& weights, int top,
                   const std::vector<float>& kernel, const TailTerm& tail, std::vector<std::vector<double>>* adjoint,
                   double* tailError) const;

    // The L1 alone against a lobe evaluated texel by texel in the pass: for measuring, where no slope
    // or tail is needed.
    double measure(const std::vector<probe::DownsampleOperator>& operators, std::vector<std::vector<double>>& weights, int top,
                   const probe::ReferenceLobe& lobe) const;

private:
    template <int ParentSlots, int RowSlots, typename Kernel>
    double measureWith(const std::vector<probe::DownsampleOperator>& operators, std::vector<std::vector<double>>& weights, int top,
                       const Kernel& kernel, const TailTerm& tail, std::vector<std::vector<double>>* adjoint, double* tailError) const;

    // The transpose of operators[0]: base texel t's parents (level-1 rows) and their weights in slots
    // [t * parentSlots_, (t + 1) * parentSlots_), rows ascending and in entry order within a row.
    // operators[0]'s rows likewise in rowSlots_ slots each. Every texel and row has the same count
    // but at the cube's corners, where the slots left are padded with weight 0 (index 0): loops of a
    // fixed count, unrolled for the B-spline and box pyramids, run faster than the operators' lists.
    int parentSlots_ = 0, rowSlots_ = 0;
    std::vector<std::uint32_t> parentRow_, rowIndex_;
    std::vector<double> parentWeight_, rowWeight_;
};

} // namespace probefit
