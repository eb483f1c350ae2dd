#include "probe/impulse_error.h"

#include "probe/reference.h"

namespace probe {

ImpulseError impulseError(const TapGenerator& generator, const std::vector<DownsampleOperator>& operators, int faceSize, int levelCount,
                          const RoughnessMapping& mapping, Lobe lobe, int level, const std::vector<WeightedTexel>& texels) {
    return impulseError([&](const Texel& texel) { return impulseWithTaps(operators, faceSize, level, texel, generator); }, faceSize,
                        levelCount, mapping, lobe, level, texels);
}

ImpulseError impulseError(const ImpulseResponse& response, int faceSize, int levelCount, const RoughnessMapping& mapping, Lobe lobe,
                          int level, const std::vector<WeightedTexel>& texels) {
    const LevelLobe levelLobe{lobe, lobeAlpha(lobe, levelAlpha(mapping, level, levelCount))};
    const CubeGeometry source(faceSize);
    const int size = faceSize >> level;
    std::vector<double> errors(texels.size());
#pragma omp parallel for schedule(dynamic, 4)
    for (std::size_t n = 0; n < texels.size(); ++n) {
        const std::vector<double> w = response(texels[n].texel);
        errors[n] = impulseL1(w, referenceKernel(texelDirection(texels[n].texel, size), source, levelLobe));
    }
    // Accumulated in texel order so the result does not depend on threads.
    ImpulseErrorAccumulator accumulator;
    for (std::size_t n = 0; n < texels.size(); ++n) accumulator.add(texels[n].texel, texels[n].weight, errors[n]);
    return accumulator.result();
}

} // namespace probe
