#include "probe/fis.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "probe/error.h"
#include "probe/ggx.h"
#include "probe/limits.h"

namespace probe {

std::string_view fisMapName(FisMap map) { return map == FisMap::paraboloid ? "paraboloid" : "cube"; }

FisMap parseFisMap(std::string_view name) {
    for (FisMap map : {FisMap::cube, FisMap::paraboloid})
        if (fisMapName(map) == name) return map;
    throw ParameterError("method.fis.map", fmt::format("{}: expected cube or paraboloid", name));
}

std::vector<Tap> fisSamples(double alpha, int faceSize, int samples, double bias, Lobe lobe) {
    std::vector<Tap> result;
    const double texelSolidAngle = 4.0 * std::numbers::pi / (6.0 * faceSize * faceSize);
    const glm::dvec3 n(0.0, 0.0, 1.0);
    const double shift = lobe == Lobe::charlie ? 0.5 : 0.0;
    for (int i = 0; i < samples; ++i) {
        const double e1 = (i + shift) / samples, e2 = radicalInverse2(static_cast<std::uint32_t>(i));
        const LobeSample s = lobeSample(lobe, e1, e2, alpha);
        const glm::dvec3& h = s.halfVector;
        const glm::dvec3 l = 2.0 * h.z * h - n;
        const double nl = l.z;
        if (nl <= 0.0) continue;
        const double sampleSolidAngle = 1.0 / (samples * s.pdf);
        result.push_back({l, 0.5 * std::log2(sampleSolidAngle / texelSolidAngle) + bias, nl});
    }
    return result;
}

void fisFrame(const glm::dvec3& R, glm::dvec3& x, glm::dvec3& y) {
    const glm::dvec3 up = std::abs(R.z) < 0.999 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(1.0, 0.0, 0.0);
    x = glm::normalize(glm::cross(up, R));
    y = glm::cross(R, x);
}

void fisTaps(const glm::dvec3& R, const std::vector<Tap>& samples, std::vector<Tap>& taps) {
    glm::dvec3 x, y;
    fisFrame(R, x, y);
    taps.clear();
    for (const Tap& s : samples) taps.push_back({x * s.direction.x + y * s.direction.y + R * s.direction.z, s.level, s.weight});
}

void validateSampleCounts(const FisSettings& settings, int levelCount) {
    if (!settings.levelSamples.empty() && static_cast<int>(settings.levelSamples.size()) != levelCount)
        throw ParameterError("method.fis.samples",
                             fmt::format("({} counts): one count, or one per output level ({})", settings.levelSamples.size(), levelCount));
    for (int m = 0; m < levelCount; ++m)
        if (settings.samplesAt(m) < 1 || settings.samplesAt(m) > kMaxSamples)
            throw ParameterError("method.fis.samples",
                                 fmt::format("{} at level {}: must be 1 to {}", settings.samplesAt(m), m, kMaxSamples));
    if (!(std::abs(settings.bias) <= kMaxFisBias))
        throw ParameterError("method.fis.bias",
                             fmt::format("{}: must be a number from -{} to {}", settings.bias, kMaxFisBias, kMaxFisBias));
}

std::vector<int> mixedLevelSamples(int samples, int levelCount) {
    std::vector<int> counts;
    for (int m = 0; m < levelCount; ++m) counts.push_back(std::min(samples << (2 * std::clamp(m - 1, 0, 2)), std::max(samples, 1024)));
    return counts;
}

std::vector<std::vector<Tap>> fisSamplesPerLevel(int faceSize, int levelCount, const RoughnessMapping& mapping, const FisSettings& settings,
                                                 Lobe lobe) {
    validateSampleCounts(settings, levelCount);
    std::vector<std::vector<Tap>> perLevel(static_cast<std::size_t>(levelCount));
    for (int m = 0; m < levelCount; ++m) {
        const double alpha = lobeAlpha(lobe, levelAlpha(mapping, m, levelCount));
        if (alpha > 0.0) perLevel[m] = fisSamples(alpha, faceSize, settings.samplesAt(m), settings.bias, lobe);
    }
    return perLevel;
}

TapGenerator fisTapGenerator(int faceSize, int levelCount, const RoughnessMapping& mapping, const FisSettings& settings, Lobe lobe) {
    // The samples of each level, made once: the generator runs per texel.
    const std::vector<std::vector<Tap>> perLevel = fisSamplesPerLevel(faceSize, levelCount, mapping, settings, lobe);
    return [=](int level, const Texel& texel, std::vector<Tap>& taps) {
        if (perLevel[level].empty()) return false;
        fisTaps(texelDirection(texel, faceSize >> level), perLevel[level], taps);
        return true;
    };
}

} // namespace probe
