#include "probe/tap_sum.h"

#include <algorithm>

#include "probe/cube_footprint.h"

namespace probe {

glm::vec3 sumTaps(const CubeLevels& pyramid, const std::vector<Tap>& taps) {
    glm::dvec3 sum(0.0);
    double weightSum = 0.0;
    for (const Tap& tap : taps) {
        sum += tap.weight * sampleTrilinear(pyramid, tap.direction, tap.level);
        weightSum += tap.weight;
    }
    if (weightSum == 0.0) return glm::vec3(0.0f);
    return glm::vec3(glm::max(sum / weightSum, glm::dvec3(0.0)));
}

std::vector<double> tapImpulseResponse(const std::vector<DownsampleOperator>& operators, int faceSize, const std::vector<Tap>& taps) {
    const int levels = pyramidLevelCount(faceSize);
    std::vector<std::vector<double>> weights(static_cast<std::size_t>(levels));
    for (int k = 0; k < levels; ++k) weights[k].assign(texelCount(faceSize >> k), 0.0);
    double weightSum = 0.0;
    for (const Tap& tap : taps) weightSum += tap.weight;
    if (weightSum == 0.0) return std::move(weights[0]);
    int top = 0;
    for (const Tap& tap : taps) {
        const TrilinearFootprint f = trilinearFootprint(faceSize, levels, toArray(tap.direction), tap.level);
        for (int k = 0; k < f.count; ++k) {
            weights[f.taps[k].level][f.taps[k].index] += tap.weight / weightSum * f.taps[k].weight;
            top = std::max(top, f.taps[k].level);
        }
    }
    pushBackToBase(operators, weights, top);
    return std::move(weights[0]);
}

CubeLevels filterWithTaps(const CubeLevels& pyramid, int levelCount, const TapGenerator& generator) {
    const int faceSize = pyramid[0].size;
    CubeLevels out;
    for (int m = 0; m < levelCount; ++m) {
        const int size = faceSize >> m;
        CubeImage level(size);
#pragma omp parallel
        {
            std::vector<Tap> taps;
#pragma omp for schedule(dynamic, 16)
            for (std::size_t t = 0; t < texelCount(size); ++t) {
                const Texel texel{static_cast<int>(t / (static_cast<std::size_t>(size) * size)), static_cast<int>(t % size),
                                  static_cast<int>(t / size % size)};
                if (generator(m, texel, taps)) level.set(t, sumTaps(pyramid, taps));
                else level.set(t, pyramid[0].texel(texelIndex(directionToTexel(texelDirection(texel, size), faceSize), faceSize)));
            }
        }
        out.push_back(std::move(level));
    }
    return out;
}

std::vector<double> impulseWithTaps(const std::vector<DownsampleOperator>& operators, int faceSize, int level, const Texel& texel,
                                    const TapGenerator& generator) {
    std::vector<Tap> taps;
    if (generator(level, texel, taps)) return tapImpulseResponse(operators, faceSize, taps);
    std::vector<double> copy(texelCount(faceSize), 0.0);
    copy[texelIndex(directionToTexel(texelDirection(texel, faceSize >> level), faceSize), faceSize)] = 1.0;
    return copy;
}

} // namespace probe
