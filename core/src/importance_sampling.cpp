#include "probe/importance_sampling.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "probe/error.h"
#include "probe/ggx.h"

namespace probe {

void importanceSampleTaps(const glm::dvec3& R, double alpha, int baseSize, const ImportanceSamplingSettings& settings,
                          std::vector<Tap>& taps) {
    taps.clear();
    const glm::dvec3 up = std::abs(R.z) < 0.999 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(1.0, 0.0, 0.0);
    const glm::dvec3 tx = glm::normalize(glm::cross(up, R)), ty = glm::cross(R, tx);
    const double alpha2 = alpha * alpha;
    const double texelSolidAngle = 4.0 * std::numbers::pi / (6.0 * baseSize * baseSize);
    for (int i = 0; i < settings.samples; ++i) {
        const double e1 = static_cast<double>(i) / settings.samples, e2 = radicalInverse2(static_cast<std::uint32_t>(i));
        const glm::dvec3 local = ggxHalfVector(e1, e2, alpha2);
        const glm::dvec3 h = tx * local.x + ty * local.y + R * local.z;
        const glm::dvec3 l = 2.0 * glm::dot(R, h) * h - R;
        const double nl = glm::dot(R, l);
        if (nl <= 0.0) continue;
        const glm::dvec3 d = R - l;
        const double pdf = ggxReflectedPdf(nl, glm::dot(d, d), alpha2);
        const double sampleSolidAngle = 1.0 / (settings.samples * pdf);
        taps.push_back({l, 0.5 * std::log2(sampleSolidAngle / texelSolidAngle) + settings.bias, nl});
    }
}

void validateSampleCounts(const ImportanceSamplingSettings& settings, int levelCount) {
    if (!settings.levelSamples.empty() && static_cast<int>(settings.levelSamples.size()) != levelCount)
        throw ProbeError(fmt::format("FIS samples per level: {} counts for {} output levels", settings.levelSamples.size(), levelCount));
    for (int m = 0; m < levelCount; ++m)
        if (settings.samplesAt(m) < 1) throw ProbeError(fmt::format("FIS samples at level {}: {} is not at least 1", m, settings.samplesAt(m)));
}

std::vector<int> mixedLevelSamples(int samples, int levelCount) {
    std::vector<int> counts;
    for (int m = 0; m < levelCount; ++m) counts.push_back(std::min(samples << (2 * std::clamp(m - 1, 0, 2)), std::max(samples, 1024)));
    return counts;
}

TapGenerator importanceSampleTapGenerator(int baseSize, int levelCount, RoughnessMapping mapping,
                                          const ImportanceSamplingSettings& settings) {
    validateSampleCounts(settings, levelCount);
    // One uniform setting per level, made once: the generator runs per texel.
    std::vector<ImportanceSamplingSettings> perLevel;
    for (int m = 0; m < levelCount; ++m) {
        perLevel.push_back(settings);
        perLevel.back().samples = settings.samplesAt(m);
        perLevel.back().levelSamples.clear();
    }
    return [=](int level, const Texel& texel, std::vector<Tap>& taps) {
        const double alpha = levelAlpha(mapping, level, levelCount);
        if (alpha <= 0.0) return false;
        importanceSampleTaps(texelDirection(texel, baseSize >> level), alpha, baseSize, perLevel[level], taps);
        return true;
    };
}

CubeLevels importanceSampleFilter(const CubeImage& source, int levelCount, RoughnessMapping mapping,
                                  const ImportanceSamplingSettings& settings) {
    validateSizeAndLevels(source.size, levelCount);
    return filterWithTaps(buildPyramid(source, settings.pyramid), levelCount,
                          importanceSampleTapGenerator(source.size, levelCount, mapping, settings));
}

std::vector<double> importanceSampleImpulseResponse(const std::vector<DownsampleOperator>& operators, int baseSize,
                                                    int levelCount, RoughnessMapping mapping,
                                                    const ImportanceSamplingSettings& settings, int level,
                                                    const Texel& texel) {
    return impulseWithTaps(operators, baseSize, level, texel,
                           importanceSampleTapGenerator(baseSize, levelCount, mapping, settings));
}

} // namespace probe
