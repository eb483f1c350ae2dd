#include "probe_outputs.h"

#include <fmt/format.h>

#include "preview.h"
#include "probe/error.h"

namespace probefilter {

std::optional<probe::Ktx2PixelFormat> parseKtx2Option(const std::string& name) {
    if (name == "none") return std::nullopt;
    if (name == "rgba16f") return probe::Ktx2PixelFormat::rgba16f;
    if (name == "rgba32f") return probe::Ktx2PixelFormat::rgba32f;
    throw probe::ProbeError(fmt::format("--ktx2: unknown format '{}' (expected none, rgba16f or rgba32f)", name));
}

void writeFilteredProbe(probe::StagedOutput& output, const probe::CubeLevels& levels, probe::RoughnessMapping mapping,
                        std::optional<probe::Ktx2PixelFormat> ktx2, nlohmann::json& report) {
    const int levelCount = static_cast<int>(levels.size());
    for (int m = 0; m < levelCount; ++m) probe::writeExr(output.file(probe::levelFileName(m)), probe::cubeToStrip(levels[m]));
    if (ktx2) {
        std::string roughness;
        for (int m = 0; m < levelCount; ++m)
            roughness += fmt::format("{}{:.6f}", m ? " " : "", probe::levelRoughness(mapping, m, levelCount));
        const probe::KeyValues metadata{{"KTXwriter", "probefilter 0.1"},
                                        {"probefilter.mapping", std::string(probe::roughnessMappingName(mapping))},
                                        {"probefilter.roughness", roughness}};
        const std::size_t clamped = probe::writeKtx2Cube(output.file("probe.ktx2"), levels, *ktx2, metadata);
        if (clamped)
            fmt::print(stderr, "probefilter: warning: {} value(s) above 65504 clamped to the half-float range in probe.ktx2\n", clamped);
        report["ktx2"] = {{"file", "probe.ktx2"},
                          {"format", *ktx2 == probe::Ktx2PixelFormat::rgba16f ? "rgba16f" : "rgba32f"},
                          {"clamped_values", clamped}};
    }
    writeLevelsPreview(output.file("preview.png"), levels);
}

} // namespace probefilter
