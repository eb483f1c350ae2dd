#include "probe/roughness.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "probe/error.h"
#include "probe/limits.h"

namespace probe {

const std::vector<std::string>& roughnessMappingNames() {
    static const std::vector<std::string> names{"gltf", "authors", "filament", "unity"};
    return names;
}

RoughnessMapping RoughnessMapping::custom(std::vector<double> roughness) {
    if (roughness.empty() || static_cast<int>(roughness.size()) > kMaxLevels)
        throw ParameterError("roughness", fmt::format("list of {} values: expected 1 to {}, one per level", roughness.size(), kMaxLevels));
    for (std::size_t m = 0; m < roughness.size(); ++m) {
        const double r = roughness[m];
        if (!(r >= 0.0 && r <= 1.0)) throw ParameterError("roughness", fmt::format("{} (level {}): expected 0 to 1", r, m));
        // The inverse (roughnessToLevel) needs one level per roughness.
        if (m > 0 && r <= roughness[m - 1])
            throw ParameterError("roughness", fmt::format("{} (level {}): not above level {}'s {}", r, m, m - 1, roughness[m - 1]));
    }
    RoughnessMapping mapping(Curve::custom);
    mapping.list_ = std::move(roughness);
    return mapping;
}

RoughnessMapping parseRoughnessMapping(std::string_view name) {
    if (name == "gltf") return RoughnessMapping::gltf;
    if (name == "authors") return RoughnessMapping::authors;
    if (name == "filament") return RoughnessMapping::filament;
    if (name == "unity") return RoughnessMapping::unity;
    throw ProbeError(fmt::format("unknown roughness mapping '{}' (expected gltf, authors, filament or unity)", name));
}

RoughnessMapping parseRoughnessList(std::string_view text) {
    std::vector<double> roughness;
    std::size_t begin = 0;
    while (begin <= text.size() && static_cast<int>(roughness.size()) <= kMaxLevels) {
        const std::size_t end = std::min(text.find(',', begin), text.size());
        const std::string_view item = text.substr(begin, end - begin);
        double value = 0.0;
        const auto [rest, error] = std::from_chars(item.data(), item.data() + item.size(), value);
        if (item.empty() || error != std::errc() || rest != item.data() + item.size())
            throw ParameterError("roughness", fmt::format("'{}': expected numbers separated by commas", text));
        roughness.push_back(value);
        begin = end + 1;
    }
    return RoughnessMapping::custom(std::move(roughness));
}

RoughnessMapping mappingFromOptions(std::string_view name, std::string_view list) {
    if (!name.empty() && !list.empty()) throw ProbeError("give --mapping or --roughness, not both");
    if (!list.empty()) return parseRoughnessList(list);
    return name.empty() ? RoughnessMapping::gltf : parseRoughnessMapping(name);
}

std::string mappingOptions(const RoughnessMapping& mapping) {
    if (mapping.curve() != RoughnessMapping::Curve::custom) return fmt::format("--mapping {}", roughnessMappingName(mapping));
    return fmt::format("--roughness {}", fmt::join(mapping.list(), ","));
}

std::string_view roughnessMappingName(const RoughnessMapping& mapping) {
    if (mapping.curve() == RoughnessMapping::Curve::custom) return "custom";
    return roughnessMappingNames()[static_cast<std::size_t>(mapping.curve())];
}

std::string describeRoughnessMapping(const RoughnessMapping& mapping) {
    if (mapping.curve() != RoughnessMapping::Curve::custom) return std::string(roughnessMappingName(mapping));
    return fmt::format("custom {}", fmt::join(mapping.list(), ","));
}

void validateMappingLevels(const RoughnessMapping& mapping, int levelCount) {
    if (mapping.curve() == RoughnessMapping::Curve::custom && static_cast<int>(mapping.list().size()) != levelCount)
        throw ParameterError("roughness",
                             fmt::format("list of {} values for {} levels: expected one per level", mapping.list().size(), levelCount));
}

double levelRoughness(const RoughnessMapping& mapping, int level, int levelCount) {
    validateMappingLevels(mapping, levelCount);
    if (mapping.curve() == RoughnessMapping::Curve::custom) return mapping.list().at(static_cast<std::size_t>(level));
    if (levelCount <= 1) return 0.0;
    const double x = static_cast<double>(level) / (levelCount - 1);
    switch (mapping.curve()) {
    case RoughnessMapping::Curve::gltf: return x;
    case RoughnessMapping::Curve::authors: {
        const double specularExponent = std::exp2(18.0 * (1.0 - x));
        return std::pow(2.0 / (1.0 + specularExponent), 0.25);
    }
    // Inverses of lod = r (2 - r) and lod = r (1.7 - 0.7 r), written to avoid cancellation.
    case RoughnessMapping::Curve::filament: return x / (1.0 + std::sqrt(1.0 - x));
    case RoughnessMapping::Curve::unity: return 2.0 * x / (1.7 + std::sqrt(2.89 - 2.8 * x));
    case RoughnessMapping::Curve::custom: break;
    }
    return x;
}

double roughnessToLevel(const RoughnessMapping& mapping, double roughness, int levelCount) {
    validateMappingLevels(mapping, levelCount);
    const double r = std::clamp(roughness, 0.0, 1.0);
    if (mapping.curve() == RoughnessMapping::Curve::custom) {
        const std::vector<double>& list = mapping.list();
        if (r <= list.front()) return 0.0;
        for (std::size_t m = 1; m < list.size(); ++m)
            if (r <= list[m]) return static_cast<double>(m - 1) + (r - list[m - 1]) / (list[m] - list[m - 1]);
        return static_cast<double>(list.size() - 1);
    }
    if (levelCount <= 1) return 0.0;
    double x = r;
    switch (mapping.curve()) {
    case RoughnessMapping::Curve::gltf: break;
    case RoughnessMapping::Curve::authors: {
        if (r <= 0.0) return 0.0;
        const double specularExponent = 2.0 / (r * r * r * r) - 1.0;
        x = 1.0 - std::log2(std::max(specularExponent, 1.0)) / 18.0;
        break;
    }
    case RoughnessMapping::Curve::filament: x = r * (2.0 - r); break;
    case RoughnessMapping::Curve::unity: x = r * (1.7 - 0.7 * r); break;
    case RoughnessMapping::Curve::custom: break;
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

int chooseLevelCount(int faceSize, std::optional<int> levels, const RoughnessMapping& mapping) {
    const bool custom = mapping.curve() == RoughnessMapping::Curve::custom;
    const int levelCount = levels.value_or(custom ? static_cast<int>(mapping.list().size()) : defaultLevelCount(faceSize));
    if (custom && !levels && log2Exact(faceSize) >= 0 && levelCount > maxLevelCount(faceSize))
        throw ParameterError("roughness", fmt::format("list of {} values, one per level: a {}^2 face has at most {} levels", levelCount,
                                                      faceSize, maxLevelCount(faceSize)));
    validateSizeAndLevels(faceSize, levelCount);
    validateMappingLevels(mapping, levelCount);
    return levelCount;
}

} // namespace probe
