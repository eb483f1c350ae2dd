// Roughness per output mip level: the mappings of docs/design.md and the level-count rules.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace probe {

enum class RoughnessMapping {
    gltf,     // r = m / (M - 1); level 0 is a copy (default)
    authors,  // Manson & Sloan: g = 1 - m / (M - 1), e = 2^(18 g), r = (2 / (1 + e))^(1/4)
    filament, // m / (M - 1) = r (2 - r)
    unity,    // m / (M - 1) = r (1.7 - 0.7 r)
};

// Parses "gltf", "authors", "filament" or "unity"; throws ProbeError naming the value otherwise.
RoughnessMapping parseRoughnessMapping(std::string_view name);
std::string_view roughnessMappingName(RoughnessMapping mapping);
const std::vector<std::string>& roughnessMappingNames();

// Perceptual roughness of output level m of M levels (0 when M = 1).
double levelRoughness(RoughnessMapping mapping, int level, int levelCount);

// GGX alpha = perceptual roughness squared.
inline double levelAlpha(RoughnessMapping mapping, int level, int levelCount) {
    const double r = levelRoughness(mapping, level, levelCount);
    return r * r;
}

// The fractional output level at which a roughness is stored (the inverse of levelRoughness).
double roughnessToLevel(RoughnessMapping mapping, double roughness, int levelCount);

// log2 of a power-of-two face size; -1 when the size is not a power of two.
int log2Exact(int size);

// Default level count for a base face size: max(1, log2(S)) (smallest face 2x2).
int defaultLevelCount(int faceSize);

// Largest valid level count: log2(S) + 1 (smallest face 1x1).
int maxLevelCount(int faceSize);

// Throws ProbeError unless faceSize is a power of two >= 1 and 1 <= levelCount <= maxLevelCount.
void validateSizeAndLevels(int faceSize, int levelCount);

} // namespace probe
