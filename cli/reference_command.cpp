// probefilter reference IN --size S [--levels M] [--mapping NAME] [--lobe ggx|charlie] --out DIR
#include <optional>

#include <fmt/format.h>
#include <omp.h>

#include "commands.h"
#include "probe/limits.h"
#include "probe/probe_io.h"
#include "probe/reference.h"
#include "probe/staged_output.h"
#include "probe_outputs.h"
#include "report.h"

namespace probefilter {

namespace {

struct ReferenceOptions {
    std::string input;
    int size = 128;
    std::optional<int> levels; // default: the mapping's list, else max(1, log2 S)
    std::string mapping;
    std::string roughness;
    std::string lobe = "ggx";
    std::string out;
    bool force = false;
    bool repairPixels = false;
    bool allowLong = false;
    std::string ktx2 = "none";
    bool ktx2Zstd = false;
};

void runReference(const ReferenceOptions& o) {
    const probe::RoughnessMapping mapping = probe::mappingFromOptions(o.mapping, o.roughness);
    const int levelCount = probe::chooseLevelCount(o.size, o.levels, mapping);
    const probe::Lobe lobe = probe::parseLobe(o.lobe);
    const std::optional<probe::Ktx2Settings> ktx2 = ktx2Options(o.ktx2, o.ktx2Zstd);
    probe::StagedOutput output(o.out, {o.input}, o.force);
    checkReferenceTime(o.size, levelCount, mapping, lobe, 1, o.allowLong);

    Stopwatch loadTime;
    nlohmann::json input, pixels;
    // The image lives only until it is a cube: at the pixel limit it is 1.5 GiB.
    const probe::CubeImage source = [&] {
        probe::Image image = probe::readImage(o.input);
        const probe::ProbeLayout layout = probe::detectLayout(image, o.input);
        const probe::PixelRepairs repairs =
            probe::checkPixels(image, o.input, o.repairPixels ? probe::BadPixelPolicy::repair : probe::BadPixelPolicy::refuse);
        pixels = reportPixelRepairs(o.input, repairs);
        input = {{"path", o.input}, {"width", image.width}, {"height", image.height}, {"layout", probe::layoutName(layout)}};
        return probe::imageToCube(image, layout, o.size);
    }();
    const double loadSeconds = loadTime.seconds();

    Stopwatch filterTime;
    const probe::CubeLevels levels = probe::referenceFilter(
        source, levelCount, mapping, [](std::size_t done, std::size_t total) { printProgress("reference", done, total); }, lobe);
    const double filterSeconds = filterTime.seconds();

    nlohmann::json report = describeLevels(o.size, levelCount, mapping, lobe);
    writeFilteredProbe(output, "", levels, mapping, ktx2, nullptr, report);
    report.update(reportHeader("reference"));
    report["input"] = input;
    report["input_pixels"] = pixels;
    report["method"] = "reference";
    report["device"] = {{"kind", "cpu"}, {"threads", omp_get_max_threads()}};
    report["passes"] = {{{"name", "load"}, {"seconds", loadSeconds}}, {{"name", "reference"}, {"seconds", filterSeconds}}};
    writeJson(output.file("report.json"), report);
    output.commit();
    fmt::print("reference: {} levels of {}^2 in {:.2f} s on {} threads -> {}\n", levelCount, o.size, filterSeconds, omp_get_max_threads(),
               o.out);
}

} // namespace

void addReferenceCommand(CLI::App& app) {
    auto options = std::make_shared<ReferenceOptions>();
    CLI::App* cmd = app.add_subcommand("reference", "Filter a probe with the exact (brute-force) GGX reference on the CPU");
    cmd->add_option("input", options->input, fmt::format("Probe image: {}", probe::kProbeImageKinds))->required();
    cmd->add_option("--size", options->size, fmt::format("Output face size S_0 (a power of two, at most {})", probe::kMaxFaceSize))
        ->required();
    cmd->add_option("--levels", options->levels, kLevelsHelp);
    cmd->add_option("--mapping", options->mapping, kMappingHelp);
    cmd->add_option("--lobe", options->lobe, kLobeHelp)->capture_default_str();
    cmd->add_option("--roughness", options->roughness, kRoughnessHelp);
    cmd->add_option("--out", options->out, "Output folder: level_<m>.exr and report.json")->required();
    cmd->add_flag("--force", options->force, kForceHelp);
    cmd->add_flag("--allow-long", options->allowLong, kAllowLongHelp);
    cmd->add_option(
        "--ktx2", options->ktx2,
        "Also write probe.ktx2: none, rgba16f, rgba32f, rgb9e5 (shared exponent, 4 bytes a texel) or bc6h (BC6H blocks encoded on "
        "the Vulkan device, 1 byte a texel)");
    cmd->add_flag("--ktx2-zstd", options->ktx2Zstd, "Store probe.ktx2's levels compressed with Zstandard (KTX2 supercompression)");
    cmd->add_flag("--repair-pixels", options->repairPixels,
                  "Set NaN and Inf pixels to 0 instead of refusing the file (negative pixels are always clamped to 0)");
    cmd->callback([options] { runReference(*options); });
}

} // namespace probefilter
