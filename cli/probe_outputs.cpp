#include "probe_outputs.h"

#include <filesystem>

#include <fmt/format.h>

#include "preview.h"
#include "probe/error.h"
#include "probe/shared_constants.h"

namespace probefilter {

std::optional<probe::Ktx2Settings> ktx2Options(const std::string& format, bool zstd) {
    if (format == "none") {
        if (zstd) throw probe::ProbeError("--ktx2-zstd: needs --ktx2 FORMAT (there is no probe.ktx2 to compress)");
        return std::nullopt;
    }
    const std::optional<probe::Ktx2PixelFormat> f = probe::parseKtx2PixelFormat(format);
    if (!f) throw probe::ProbeError(fmt::format("--ktx2: unknown format '{}' (expected none, rgba16f, rgba32f, rgb9e5 or bc6h)", format));
    return probe::Ktx2Settings{*f, zstd ? probe::Ktx2Supercompression::zstd : probe::Ktx2Supercompression::none};
}

namespace {

// BC6H's range: unsigned half floats.
std::size_t outsideBc6hRange(const probe::CubeLevels& levels) {
    std::size_t outside = 0;
    for (const probe::CubeImage& level : levels)
        for (float v : level.rgb) outside += v < 0.0f || v > float(PROBE_HALF_MAX);
    return outside;
}

} // namespace

nlohmann::json writeProbeKtx2(probe::StagedOutput& output, const std::string& name, const probe::CubeLevels& levels,
                              probe::RoughnessMapping mapping, probe::Ktx2Settings settings, const probe::gpu::Device* device) {
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
    std::size_t clamped = 0;
    std::optional<double> encodeMs;
    if (settings.format == probe::Ktx2PixelFormat::bc6h) {
        std::optional<probe::gpu::Device> own;
        probe::gpu::Bc6hEncoder encoder(device ? *device : own.emplace(), faceSize, levelCount);
        probe::writeKtx2Bc6hCube(output.file(name), faceSize, encoder.encode(filled), metadata, settings.supercompression);
        clamped = outsideBc6hRange(filled);
        for (const probe::gpu::PassTime& t : encoder.timings())
            if (t.name == "total") encodeMs = t.medianMs;
    } else {
        clamped = probe::writeKtx2Cube(output.file(name), filled, settings.format, metadata, settings.supercompression);
    }
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
    if (encodeMs) report["encode_gpu_ms"] = *encodeMs;
    return report;
}

void writeFilteredProbe(probe::StagedOutput& output, const std::string& folder, const probe::CubeLevels& levels,
                        const probe::RoughnessMapping& mapping, std::optional<probe::Ktx2Settings> ktx2, const probe::gpu::Device* device,
                        nlohmann::json& report) {
    const int levelCount = static_cast<int>(levels.size());
    for (int m = 0; m < levelCount; ++m) probe::writeExr(output.file(folder + probe::levelFileName(m)), probe::cubeToStrip(levels[m]));
    if (ktx2) report["ktx2"] = writeProbeKtx2(output, folder + "probe.ktx2", levels, mapping, *ktx2, device);
    writeLevelsPreview(output.file(folder + "preview.png"), levels);
}

} // namespace probefilter
