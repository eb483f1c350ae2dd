#include "probe_outputs.h"

#include <filesystem>

#include <fmt/format.h>

#include "preview.h"
#include "probe/error.h"

namespace probefilter {

std::optional<probe::Ktx2Settings> ktx2Options(const std::string& format, bool zstd) {
    if (format == "none") {
        if (zstd) throw probe::ProbeError("--ktx2-zstd: needs --ktx2 FORMAT (there is no probe.ktx2 to compress)");
        return std::nullopt;
    }
    const std::optional<probe::Ktx2PixelFormat> f = probe::parseKtx2PixelFormat(format);
    if (!f) throw probe::ProbeError(fmt::format("--ktx2: unknown format '{}' (expected none, rgba16f, rgba32f or rgb9e5)", format));
    return probe::Ktx2Settings{*f, zstd ? probe::Ktx2Supercompression::zstd : probe::Ktx2Supercompression::none};
}

nlohmann::json writeProbeKtx2(probe::StagedOutput& output, const std::string& name, const probe::CubeLevels& levels,
                              probe::RoughnessMapping mapping, probe::Ktx2Settings settings) {
    const int levelCount = static_cast<int>(levels.size());
    int faceSize = 0;
    for (int m = levelCount; m-- > 0;)
        if (levels[m].size) faceSize = levels[m].size << m;
    std::string roughness, computed;
    probe::CubeLevels filled = levels;
    bool partial = false;
    for (int m = 0; m < levelCount; ++m) {
        roughness += fmt::format("{}{:.6f}", m ? " " : "", probe::levelRoughness(mapping, m, levelCount));
        if (levels[m].size == 0) {
            filled[m] = probe::CubeImage(faceSize >> m); // black: no material reads it
            partial = true;
        } else {
            computed += fmt::format("{}{}", computed.empty() ? "" : " ", m);
        }
    }
    probe::KeyValues metadata{{"KTXwriter", "probefilter 0.1"},
                              {"probefilter.mapping", probe::describeRoughnessMapping(mapping)},
                              {"probefilter.roughness", roughness}};
    if (partial) metadata.push_back({"probefilter.computed_levels", computed});
    const std::size_t clamped = probe::writeKtx2Cube(output.file(name), filled, settings.format, metadata, settings.supercompression);
    if (clamped)
        probe::printToStderr(fmt::format("probefilter: warning: {} value(s) outside the {} range clamped to it in {}\n", clamped,
                                         probe::ktx2FormatName(settings.format), name));
    const bool zstd = settings.supercompression == probe::Ktx2Supercompression::zstd;
    nlohmann::json report = {{"file", name},
                             {"format", probe::ktx2FormatName(settings.format)},
                             {"supercompression", zstd ? "zstd" : "none"},
                             {"bytes", std::filesystem::file_size(output.file(name))},
                             {"clamped_values", clamped}};
    if (partial) report["computed_levels"] = computed;
    return report;
}

void writeFilteredProbe(probe::StagedOutput& output, const std::string& folder, const probe::CubeLevels& levels,
                        const probe::RoughnessMapping& mapping, std::optional<probe::Ktx2Settings> ktx2, nlohmann::json& report) {
    const int levelCount = static_cast<int>(levels.size());
    for (int m = 0; m < levelCount; ++m) probe::writeExr(output.file(folder + probe::levelFileName(m)), probe::cubeToStrip(levels[m]));
    if (ktx2) report["ktx2"] = writeProbeKtx2(output, folder + "probe.ktx2", levels, mapping, *ktx2);
    writeLevelsPreview(output.file(folder + "preview.png"), levels);
}

} // namespace probefilter
