// Roughness per output mip level: the mappings of docs/design.md, a user's own list, and the
// level-count rules.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "probe/limits.h"

namespace probe {

// Which perceptual roughness each output level holds: one of the named curves, or a list of its own
// (one roughness per level). A value type: compare with ==, copy freely.
class RoughnessMapping {
public:
    enum class Curve {
        gltf,     // r = m / (M - 1); level 0 is a copy (default)
        authors,  // Manson & Sloan: g = 1 - m / (M - 1), e = 2^(18 g), r = (2 / (1 + e))^(1/4)
        filament, // m / (M - 1) = r (2 - r)
        unity,    // m / (M - 1) = r (1.7 - 0.7 r)
        custom,   // the list: level m has roughness list[m]
    };
    static const RoughnessMapping gltf, authors, filament, unity;

    RoughnessMapping() = default;
    // A list of perceptual roughness, level 0 first: finite, in [0, 1], strictly increasing, at most
    // kMaxLevels values. Throws ParameterError("roughness", ...) otherwise.
    static RoughnessMapping custom(std::vector<double> roughness);

    Curve curve() const { return curve_; }
    const std::vector<double>& list() const { return list_; } // empty unless custom
    bool operator==(const RoughnessMapping& other) const { return curve_ == other.curve_ && list_ == other.list_; }
    bool operator!=(const RoughnessMapping& other) const { return !(*this == other); }

private:
    explicit RoughnessMapping(Curve curve) : curve_(curve) {}
    Curve curve_ = Curve::gltf;
    std::vector<double> list_;
};

inline const RoughnessMapping RoughnessMapping::gltf{Curve::gltf};
inline const RoughnessMapping RoughnessMapping::authors{Curve::authors};
inline const RoughnessMapping RoughnessMapping::filament{Curve::filament};
inline const RoughnessMapping RoughnessMapping::unity{Curve::unity};

// Parses "gltf", "authors", "filament" or "unity"; throws ProbeError naming the value otherwise.
RoughnessMapping parseRoughnessMapping(std::string_view name);
// Parses a comma-separated roughness list ("0,0.25,0.5,1") into a custom mapping; throws ParameterError.
RoughnessMapping parseRoughnessList(std::string_view text);
// A command line's --mapping NAME and --roughness LIST, at most one of them given (empty: not given);
// neither: gltf.
RoughnessMapping mappingFromOptions(std::string_view name, std::string_view list);
// The options that select the mapping: "--mapping NAME" or "--roughness LIST".
std::string mappingOptions(const RoughnessMapping& mapping);
// "gltf", "authors", "filament", "unity" or "custom".
std::string_view roughnessMappingName(const RoughnessMapping& mapping);
// The named curves (not custom).
const std::vector<std::string>& roughnessMappingNames();
// What a report or a table records: the name, and for custom also the list ("custom 0,0.3,1").
std::string describeRoughnessMapping(const RoughnessMapping& mapping);

// Throws ParameterError("roughness", ...) unless the mapping has `levelCount` levels: a custom list
// must hold exactly one value per level.
void validateMappingLevels(const RoughnessMapping& mapping, int levelCount);

// Perceptual roughness of output level m of M levels (0 when M = 1 for the named curves).
double levelRoughness(const RoughnessMapping& mapping, int level, int levelCount);

// GGX alpha = perceptual roughness squared.
inline double levelAlpha(const RoughnessMapping& mapping, int level, int levelCount) {
    const double r = levelRoughness(mapping, level, levelCount);
    return r * r;
}

// The fractional output level at which a roughness is stored (the inverse of levelRoughness;
// piecewise linear between a custom list's levels, clamped to its ends).
double roughnessToLevel(const RoughnessMapping& mapping, double roughness, int levelCount);

// log2 of a power-of-two face size; -1 when the size is not a power of two.
int log2Exact(int size);

// Default level count for a base face size: max(1, log2(S)) (smallest face 2x2).
int defaultLevelCount(int faceSize);

// Largest valid level count: log2(S) + 1 (smallest face 1x1).
int maxLevelCount(int faceSize);

// Throws ProbeError unless faceSize is a power of two >= 1 and 1 <= levelCount <= maxLevelCount.
void validateSizeAndLevels(int faceSize, int levelCount);

// The level count a run uses: `levels` where given, else a custom list's length, else
// defaultLevelCount(faceSize); validated against the face size and the mapping.
int chooseLevelCount(int faceSize, std::optional<int> levels, const RoughnessMapping& mapping);

} // namespace probe
