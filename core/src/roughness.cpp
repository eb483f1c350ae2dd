#include "probe/roughness.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/limits.h"

namespace probe {

const std::vector<std::string>& roughnessMappingNames() {
    static const std::vector<std::string> names{"gltf", "authors", "filament", "unity"};
    return names;
}

RoughnessMapping parseRoughnessMapping(std::string_view name) {
    if (name == "gltf") return RoughnessMapping::gltf;
    if (name == "authors") return RoughnessMapping::authors;
    if (name == "filament") return RoughnessMapping::filament;
    if (name == "unity") return RoughnessMapping::unity;
    throw ProbeError(fmt::format("unknown roughness mapping '{}' (expected gltf, authors, filament or unity)", name));
}

std::string_view roughnessMappingName(RoughnessMapping mapping) { return roughnessMappingNames()[static_cast<std::size_t>(mapping)]; }

double levelRoughness(RoughnessMapping mapping, int level, int levelCount) {
    if (levelCount <= 1) return 0.0;
    const double x = static_cast<double>(level) / (levelCount - 1);
    switch (mapping) {
    case RoughnessMapping::gltf: return x;
    case RoughnessMapping::authors: {
        const double specularExponent = std::exp2(18.0 * (1.0 - x));
        return std::pow(2.0 / (1.0 + specularExponent), 0.25);
    }
    // Inverses of lod = r (2 - r) and lod = r (1.7 - 0.7 r), written to avoid cancellation.
    case RoughnessMapping::filament: return x / (1.0 + std::sqrt(1.0 - x));
    case RoughnessMapping::unity: return 2.0 * x / (1.7 + std::sqrt(2.89 - 2.8 * x));
    }
    return x;
}

double roughnessToLevel(RoughnessMapping mapping, double roughness, int levelCount) {
    if (levelCount <= 1) return 0.0;
    const double r = std::clamp(roughness, 0.0, 1.0);
    double x = r;
    switch (mapping) {
    case RoughnessMapping::gltf: break;
    case RoughnessMapping::authors: {
        if (r <= 0.0) return 0.0;
        const double specularExponent = 2.0 / (r * r * r * r) - 1.0;
        x = 1.0 - std::log2(std::max(specularExponent, 1.0)) / 18.0;
        break;
    }
    case RoughnessMapping::filament: x = r * (2.0 - r); break;
    case RoughnessMapping::unity: x = r * (1.7 - 0.7 * r); break;
    }
    return std::clamp(x, 0.0, 1.0) * (levelCount - 1);
}

int log2Exact(int size) {
    if (size < 1 || (size & (size - 1)) != 0) return -1;
    int log = 0;
    while ((1 << log) < size) ++log;
    return log;
}

int defaultLevelCount(int faceSize) { return std::max(1, log2Exact(faceSize)); }

int maxLevelCount(int faceSize) { return log2Exact(faceSize) + 1; }

void validateSizeAndLevels(int faceSize, int levelCount) {
    if (log2Exact(faceSize) < 0) throw ProbeError(fmt::format("face size {} is not a power of two >= 1", faceSize));
    if (faceSize > kMaxFaceSize) throw ProbeError(fmt::format("face size {} is over the limit of {}", faceSize, kMaxFaceSize));
    if (levelCount < 1 || levelCount > maxLevelCount(faceSize))
        throw ProbeError(
            fmt::format("level count {} is impossible for face size {} (1..{})", levelCount, faceSize, maxLevelCount(faceSize)));
}

} // namespace probe
