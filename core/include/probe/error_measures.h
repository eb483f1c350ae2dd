// The two error measures of docs/design.md.
#pragma once

#include <vector>

#include "probe/cube_image.h"

namespace probe {

// e(R) = sum_t |w(R, t) - k(R, t)| for one output texel, both weight vectors normalized to sum 1
// first; lies in [0, 2].
double impulseL1(const std::vector<double>& methodWeights, const std::vector<double>& referenceWeights);

// Per level: the solid-angle weighted mean of e over output texels, and the worst texel.
struct ImpulseError {
    double mean = 0.0;
    double max = 0.0;
    Texel worst{};
};

// Accumulates e(R) over the output texels of one level.
class ImpulseErrorAccumulator {
public:
    void add(const Texel& texel, double solidAngle, double error);
    ImpulseError result() const;

private:
    double weightedSum_ = 0.0;
    double solidAngleSum_ = 0.0;
    ImpulseError worst_{};
};

// sum |out - ref| dOmega / sum |ref| dOmega over texels and RGB of one level (0 when both are black).
double imageL1(const CubeImage& out, const CubeImage& reference);

} // namespace probe
