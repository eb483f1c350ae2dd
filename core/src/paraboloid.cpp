#include "probe/paraboloid.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "probe/error.h"

namespace probe {

namespace {

std::size_t imageTexels(int size) { return static_cast<std::size_t>(size) * size; }

// Up to 8 map texels (level, index within the level) and their weights: bilinear with clamp-to-edge
// addressing in the levels floor(level) and floor(level) + 1, lerped.
TrilinearFootprint paraboloidFootprint(int size0, int levelCount, const glm::dvec3& direction, double level) {
    level = std::clamp(level, 0.0, static_cast<double>(levelCount - 1));
    const int lower = static_cast<int>(std::floor(level));
    const double upperWeight = level - lower;
    TrilinearFootprint out;
    const auto add = [&](int k, double levelWeight) {
        const int size = size0 >> k;
        const ParaboloidPoint p = paraboloidPoint(direction, size);
        const int i0 = static_cast<int>(std::floor(p.x - 0.5)), j0 = static_cast<int>(std::floor(p.y - 0.5));
        const double fx = p.x - (i0 + 0.5), fy = p.y - (j0 + 0.5);
        const double w[4] = {(1.0 - fx) * (1.0 - fy), fx * (1.0 - fy), (1.0 - fx) * fy, fx * fy};
        for (int t = 0; t < 4; ++t) {
            const int i = std::clamp(i0 + (t & 1), 0, size - 1), j = std::clamp(j0 + (t >> 1), 0, size - 1);
            const std::size_t index = static_cast<std::size_t>(p.image) * imageTexels(size) + static_cast<std::size_t>(j) * size + i;
            out.taps[out.count++] = {k, static_cast<std::uint32_t>(index), w[t] * levelWeight};
        }
    };
    add(lower, 1.0 - upperWeight);
    if (lower + 1 < levelCount && upperWeight > 0.0) add(lower + 1, upperWeight);
    return out;
}

int mapLevelCount(int size) { return static_cast<int>(std::log2(size)) + 1; }

} // namespace

ParaboloidPoint paraboloidPoint(const glm::dvec3& direction, int size) {
    const glm::dvec3 d = glm::normalize(direction);
    const int image = d.z >= 0.0 ? 0 : 1;
    const double denominator = 1.0 + std::abs(d.z);
    const double half = 0.5 * size;
    return {image, (d.x / denominator * PROBE_PARABOLOID_SCALE + 1.0) * half, (d.y / denominator * PROBE_PARABOLOID_SCALE + 1.0) * half};
}

glm::dvec3 paraboloidDirection(int image, double x, double y, int size) {
    const double u = (2.0 * x / size - 1.0) / PROBE_PARABOLOID_SCALE, v = (2.0 * y / size - 1.0) / PROBE_PARABOLOID_SCALE;
    const double r2 = u * u + v * v;
    const double z = (1.0 - r2) / (1.0 + r2);
    return {2.0 * u / (1.0 + r2), 2.0 * v / (1.0 + r2), image == 0 ? z : -z};
}

double paraboloidTexelSolidAngle(const glm::dvec3& direction, int size) {
    const glm::dvec3 d = glm::normalize(direction);
    const double denominator = 1.0 + std::abs(d.z);
    const double u = d.x / denominator, v = d.y / denominator;
    const double texel = 2.0 / (PROBE_PARABOLOID_SCALE * size); // a texel's side in (u, v)
    const double jacobian = 4.0 / ((1.0 + u * u + v * v) * (1.0 + u * u + v * v));
    return jacobian * texel * texel;
}

double paraboloidLevel(const glm::dvec3& direction, double cubeLevel, int faceSize) {
    const double cubeTexel = 4.0 * std::numbers::pi / (6.0 * faceSize * faceSize);
    return cubeLevel + 0.5 * std::log2(cubeTexel / paraboloidTexelSolidAngle(direction, paraboloidSize(faceSize)));
}

ParaboloidMap buildParaboloidMap(const CubeImage& source) {
    ParaboloidMap map;
    map.size = paraboloidSize(source.size);
    const int size = map.size;
    std::vector<glm::vec3> level0(2 * imageTexels(size));
#pragma omp parallel for schedule(static)
    for (int row = 0; row < 2 * size; ++row) {
        const int image = row / size, j = row % size;
        for (int i = 0; i < size; ++i)
            level0[static_cast<std::size_t>(row) * size + i] =
                glm::vec3(sampleBilinear(source, paraboloidDirection(image, i + 0.5, j + 0.5, size)));
    }
    map.levels.push_back(std::move(level0));
    for (int k = 1; k < mapLevelCount(size); ++k) {
        const int s = size >> k;
        const std::vector<glm::vec3>& fine = map.levels.back();
        std::vector<glm::vec3> coarse(2 * imageTexels(s));
        for (int image = 0; image < 2; ++image)
            for (int j = 0; j < s; ++j)
                for (int i = 0; i < s; ++i) {
                    const std::size_t f = image * imageTexels(2 * s) + static_cast<std::size_t>(2 * j) * (2 * s) + 2 * i;
                    coarse[image * imageTexels(s) + static_cast<std::size_t>(j) * s + i] =
                        0.25f * (fine[f] + fine[f + 1] + fine[f + 2 * s] + fine[f + 2 * s + 1]);
                }
        map.levels.push_back(std::move(coarse));
    }
    return map;
}

glm::dvec3 sampleParaboloid(const ParaboloidMap& map, const glm::dvec3& direction, double level) {
    const TrilinearFootprint f = paraboloidFootprint(map.size, map.levelCount(), direction, level);
    glm::dvec3 value(0.0);
    for (int t = 0; t < f.count; ++t) value += f.taps[t].weight * glm::dvec3(map.levels[f.taps[t].level][f.taps[t].index]);
    return value;
}

CubeLevels paraboloidFilter(const CubeImage& source, int levelCount, const RoughnessMapping& mapping, const FisSettings& settings) {
    validateSizeAndLevels(source.size, levelCount);
    const ParaboloidMap map = buildParaboloidMap(source);
    const std::vector<std::vector<Tap>> samples = fisSamplesPerLevel(source.size, levelCount, mapping, settings);
    CubeLevels out;
    for (int m = 0; m < levelCount; ++m) {
        const int size = source.size >> m;
        if (levelAlpha(mapping, m, levelCount) <= 0.0) {
            out.push_back(source); // level 0, the only one with alpha = 0
            continue;
        }
        CubeImage level(size);
#pragma omp parallel
        {
            std::vector<Tap> taps;
#pragma omp for schedule(dynamic, 16)
            for (std::size_t t = 0; t < texelCount(size); ++t) {
                const Texel texel{static_cast<int>(t / imageTexels(size)), static_cast<int>(t % size), static_cast<int>(t / size % size)};
                fisTaps(texelDirection(texel, size), samples[m], taps);
                glm::dvec3 sum(0.0);
                double weightSum = 0.0;
                for (const Tap& tap : taps) {
                    sum += tap.weight * sampleParaboloid(map, tap.direction, paraboloidLevel(tap.direction, tap.level, source.size));
                    weightSum += tap.weight;
                }
                level.set(t, weightSum > 0.0 ? glm::vec3(glm::max(sum / weightSum, glm::dvec3(0.0))) : glm::vec3(0.0f));
            }
        }
        out.push_back(std::move(level));
    }
    return out;
}

ParaboloidImpulse::ParaboloidImpulse(int faceSize, int levelCount, const RoughnessMapping& mapping, const FisSettings& settings)
    : faceSize_(faceSize), levelCount_(levelCount), mapping_(mapping),
      samples_(fisSamplesPerLevel(faceSize, levelCount, mapping, settings)) {
    const int size = paraboloidSize(faceSize);
    source_.resize(2 * imageTexels(size));
    for (int image = 0; image < 2; ++image)
        for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i)
                source_[image * imageTexels(size) + static_cast<std::size_t>(j) * size + i] =
                    bilinearFootprint(faceSize, toArray(paraboloidDirection(image, i + 0.5, j + 0.5, size)));
}

std::vector<double> ParaboloidImpulse::response(int level, const Texel& texel) const {
    if (levelAlpha(mapping_, level, levelCount_) <= 0.0)
        throw ProbeError("paraboloid impulse response: level " + std::to_string(level) + " is a copy (alpha = 0)");
    const int size = paraboloidSize(faceSize_), levels = mapLevelCount(size);
    std::vector<Tap> taps;
    fisTaps(texelDirection(texel, faceSize_ >> level), samples_[level], taps);
    double weightSum = 0.0;
    for (const Tap& tap : taps) weightSum += tap.weight;
    std::vector<std::vector<double>> weights(static_cast<std::size_t>(levels));
    for (int k = 0; k < levels; ++k) weights[k].assign(2 * imageTexels(size >> k), 0.0);
    for (const Tap& tap : taps) {
        const TrilinearFootprint f = paraboloidFootprint(size, levels, tap.direction, paraboloidLevel(tap.direction, tap.level, faceSize_));
        for (int t = 0; t < f.count; ++t) weights[f.taps[t].level][f.taps[t].index] += tap.weight / weightSum * f.taps[t].weight;
    }
    // Each mip texel is the mean of its four children: its weight goes a quarter to each.
    for (int k = levels - 1; k >= 1; --k) {
        const int s = size >> k;
        for (int image = 0; image < 2; ++image)
            for (int j = 0; j < s; ++j)
                for (int i = 0; i < s; ++i) {
                    const double w = weights[k][image * imageTexels(s) + static_cast<std::size_t>(j) * s + i];
                    if (w == 0.0) continue;
                    const std::size_t f = image * imageTexels(2 * s) + static_cast<std::size_t>(2 * j) * (2 * s) + 2 * i;
                    for (const std::size_t c : {f, f + 1, f + 2 * s, f + 2 * s + 1}) weights[k - 1][c] += 0.25 * w;
                }
    }
    std::vector<double> base(texelCount(faceSize_), 0.0);
    for (std::size_t t = 0; t < source_.size(); ++t) {
        const double w = weights[0][t];
        if (w == 0.0) continue;
        for (int k = 0; k < source_[t].count; ++k) base[source_[t].taps[k].index] += w * source_[t].taps[k].weight;
    }
    return base;
}

} // namespace probe
