// probefilter compare IN --size S --out DIR: the talks' comparison, as a picture and numbers. The
// exact CPU reference, the tap table and FIS-32 (about the same GPU time) filter the probe; metal
// spheres of a few roughnesses are rendered with each (probe::gpu::renderSpheres) and laid out with
// heat maps of their error against the reference's (sheet.png); report.json holds the image L1 per
// level, the spheres' L1 and the GPU times.
#include <array>
#include <filesystem>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "bench_commands.h"
#include "commands.h"
#include "comparison_sheet.h"
#include "preview.h"
#include "probe/dfg.h"
#include "probe/error.h"
#include "probe/error_measures.h"
#include "probe/limits.h"
#include "probe/probe_io.h"
#include "probe/reference.h"
#include "probe/staged_output.h"
#include "probe/table_io.h"
#include "report.h"
#include "spheres.h"
#include "table_option.h"

namespace probefilter {

namespace {

using nlohmann::json;

struct CompareOptions {
    std::string input;
    int size = 128;
    int levels = 0;    // 0: the default for the size
    std::string table; // a table file; default: the compiled-in table for the settings
    int samples = 32;
    std::vector<double> roughness{0.15, 0.3, 0.5, 0.75, 1.0};
    int cell = 128;
    double maxError = 0.2;
    int repeat = 3;
    std::string sampling = "automatic";
    std::string device;
    bool validate = false;
    bool repairPixels = false;
    std::string out;
    bool force = false;
    bool allowLong = false;
};

struct MethodRun {
    probe::CubeLevels levels;
    double gpuMs = 0.0;
    probe::gpu::Sampling sampling = probe::gpu::Sampling::exact;
};

// The table and FIS filter the probe once each (their outputs; a first run also pays one-time
// costs), then run in turns, `repeat` rounds, so that a machine whose speed drifts slows both alike:
// each one's GPU time is the median over the rounds.
std::array<MethodRun, 2> runInTurns(const probe::gpu::Device& device, const std::array<probe::gpu::FilterSettings, 2>& settings,
                                    const probe::CubeImage& source, int repeat) {
    std::array<std::unique_ptr<probe::gpu::Filter>, 2> filters;
    std::array<MethodRun, 2> runs;
    for (std::size_t k = 0; k < filters.size(); ++k) {
        filters[k] = std::make_unique<probe::gpu::Filter>(device, settings[k]);
        runs[k].levels = filters[k]->run(source);
        runs[k].sampling = filters[k]->sampling();
    }
    std::array<std::vector<double>, 2> totals;
    for (int round = 0; round < repeat; ++round)
        for (std::size_t k = 0; k < filters.size(); ++k) {
            filters[k]->run(source);
            for (const probe::gpu::PassTime& t : filters[k]->timings())
                if (t.name == "total") totals[k].push_back(t.medianMs);
        }
    for (std::size_t k = 0; k < runs.size(); ++k) runs[k].gpuMs = median(totals[k]);
    return runs;
}

json levelErrors(const probe::CubeLevels& levels, const probe::CubeLevels& reference) {
    json errors = json::array();
    for (std::size_t m = 0; m < levels.size(); ++m) errors.push_back(probe::imageL1(levels[m], reference[m]));
    return errors;
}

// The options no settings check covers: the sheet's spheres, cells and heat map, the repeats, FIS.
void checkCompareOptions(const CompareOptions& o) {
    if (o.roughness.empty() || o.roughness.size() > probe::kMaxSheetSpheres)
        throw probe::ProbeError(fmt::format("--roughness: give 1 to {} values", probe::kMaxSheetSpheres));
    for (double r : o.roughness)
        if (!(r >= 0.0 && r <= 1.0)) throw probe::ProbeError(fmt::format("--roughness {}: outside [0, 1]", r));
    if (o.cell < 8 || o.cell > probe::kMaxSheetCell)
        throw probe::ProbeError(fmt::format("--cell {}: must be 8 to {} pixels", o.cell, probe::kMaxSheetCell));
    probe::checkRepeat(o.repeat);
    if (o.samples < 1 || o.samples > probe::kMaxSamples)
        throw probe::ProbeError(fmt::format("--samples {}: must be 1 to {}", o.samples, probe::kMaxSamples));
    // The heat maps' white: a relative error, shown in the legend as a percentage.
    if (!(o.maxError >= 1e-6 && o.maxError <= 1e6))
        throw probe::ProbeError(fmt::format("--max-error {}: must be a relative error from 1e-06 to 1e+06", o.maxError));
}

// The table's settings and FIS's, alike but for the method; the table (--table, or the compiled-in
// one for the shape) goes into `table`.
std::array<probe::gpu::FilterSettings, 2> compareSettings(const CompareOptions& o, int levelCount, const probe::RoughnessMapping& mapping,
                                                          probe::TapTable& table) {
    probe::gpu::FilterSettings tableSettings;
    tableSettings.method.kind = probe::MethodKind::table;
    tableSettings.sampling = probe::gpu::parseSampling(o.sampling);
    tableSettings.faceSize = o.size;
    tableSettings.levelCount = levelCount;
    tableSettings.mapping = mapping;
    if (!o.table.empty()) {
        table = tableOption(o.table);
    } else if (const probe::gpu::CompiledTable* compiled =
                   probe::gpu::findCompiledTable(o.size, levelCount, mapping, {}, probe::Lobe::ggx)) {
        table = compiled->table;
    } else {
        throw probe::ProbeError(
            fmt::format("no compiled-in tap table for {}^2, {} levels, gltf mapping; pass --table NAME|FILE", o.size, levelCount));
    }
    tableSettings.method.table = &table;
    // A table that does not fit is refused before the reference's minutes of CPU.
    probe::validateMethod(tableSettings.method, o.size, levelCount, mapping);
    probe::gpu::FilterSettings fisSettings = tableSettings;
    fisSettings.method = {probe::MethodKind::fis, nullptr, {}};
    fisSettings.method.fis.samples = o.samples;
    return {tableSettings, fisSettings};
}

// The sheet's spheres (metals of the roughness asked for) into `scene`; their description for the report.
json addSheetSpheres(const CompareOptions& o, const probe::RoughnessMapping& mapping, int levelCount, probe::gpu::SphereScene& scene) {
    json materials = json::array();
    for (double r : o.roughness) {
        probe::SceneMaterial m;
        m.name = fmt::format("metal r={}", r);
        m.roughness = r;
        m.metallic = 1.0;
        m.baseColor = glm::dvec3(0.95, 0.93, 0.88);
        scene.materials.push_back(sphereMaterial(m, mapping, levelCount));
        materials.push_back({{"roughness", r}, {"level", scene.materials.back().level}, {"metallic", 1.0}});
    }
    return materials;
}

void runCompare(const CompareOptions& o) {
    const probe::RoughnessMapping mapping = probe::RoughnessMapping::gltf;
    const int levelCount = o.levels == 0 ? probe::defaultLevelCount(o.size) : o.levels;
    probe::validateSizeAndLevels(o.size, levelCount);
    checkCompareOptions(o);
    probe::TapTable table;
    const auto [tableSettings, fisSettings] = compareSettings(o, levelCount, mapping, table);

    std::vector<std::filesystem::path> inputs{o.input};
    if (!o.table.empty() && std::filesystem::exists(o.table)) inputs.emplace_back(o.table);
    probe::StagedOutput output(o.out, inputs, o.force);
    checkReferenceTime(o.size, levelCount, mapping, probe::Lobe::ggx, 1, o.allowLong);
    probe::gpu::DeviceOptions deviceOptions;
    deviceOptions.choice = o.device;
    deviceOptions.validation = o.validate;
    const probe::gpu::Device device(deviceOptions);
    for (const probe::gpu::FilterSettings& settings : {tableSettings, fisSettings}) probe::gpu::Filter::checkLimits(device, settings);
    probe::PixelRepairs repairs;
    const probe::CubeImage source =
        probe::loadProbe(o.input, o.size, o.repairPixels ? probe::BadPixelPolicy::repair : probe::BadPixelPolicy::refuse, repairs);
    const nlohmann::json pixels = reportPixelRepairs(o.input, repairs);

    const Stopwatch referenceClock;
    const probe::CubeLevels reference = probe::referenceFilter(
        source, levelCount, mapping, [](std::size_t done, std::size_t total) { printProgress("reference", done, total); });
    const double referenceSeconds = referenceClock.seconds();
    const auto [tableRun, fisRun] = runInTurns(device, {tableSettings, fisSettings}, source, o.repeat);

    const probe::Image dfg = probe::dfgTable(probe::kDfgTableSize, probe::kDfgTableSamples);
    probe::gpu::SphereScene scene;
    scene.background = &source;
    scene.dfg = &dfg;
    scene.cellSize = o.cell;
    const json materials = addSheetSpheres(o, mapping, levelCount, scene);
    auto render = [&](const probe::CubeLevels& levels) {
        scene.prefiltered = &levels;
        return probe::gpu::renderSpheres(device, scene);
    };
    const std::vector<SheetRow> rows{
        {fmt::format("REFERENCE (CPU, {:.1f} S)", referenceSeconds), render(reference)},
        {fmt::format("TABLE {}X3 {} ({:.2f} MS)", table.taps, probe::tableFormName(table.form), tableRun.gpuMs), render(tableRun.levels)},
        {fmt::format("FIS {} ({:.2f} MS)", o.samples, fisRun.gpuMs), render(fisRun.levels)},
    };
    writeComparisonSheet(output.file("sheet.png"), rows, autoExposure(source), o.maxError);
    const std::vector<std::string> messages = device.validationMessages();
    if (!messages.empty())
        throw probe::ProbeError(
            fmt::format("the Vulkan validation layer reported {} message(s); the first: {}", messages.size(), messages.front()));

    json report = describeLevels(o.size, levelCount, mapping, probe::Lobe::ggx);
    report.update(reportHeader("compare"));
    report["input"] = o.input;
    report["input_pixels"] = pixels;
    report["device"] = describeDevice(device.info(), o.validate);
    report["sheet"] = {{"file", "sheet.png"},
                       {"rows", {"reference", "table", "fis"}},
                       {"spheres", materials},
                       {"heat_map", fmt::format("per pixel sum_c |x - ref| / sum_c ref, black 0 to white {}", o.maxError)}};
    report["reference"] = {{"cpu_seconds", referenceSeconds}};
    report["table"] = {{"taps_per_frame", table.taps},
                       {"form", std::string(probe::tableFormName(table.form))},
                       {"gpu_ms_median", tableRun.gpuMs},
                       {"image_l1_per_level", levelErrors(tableRun.levels, reference)},
                       {"spheres_l1", spheresL1(rows[1].spheres, rows[0].spheres)}};
    report["fis"] = {{"samples", o.samples},
                     {"bias", 0.0},
                     {"gpu_ms_median", fisRun.gpuMs},
                     {"image_l1_per_level", levelErrors(fisRun.levels, reference)},
                     {"spheres_l1", spheresL1(rows[2].spheres, rows[0].spheres)}};
    report["sampling"] = std::string(probe::gpu::samplingName(tableRun.sampling));
    report["repeat"] = o.repeat;
    writeJson(output.file("report.json"), report);
    output.commit();
    fmt::print("compare: spheres L1 against the reference: table {:.4f} ({:.2f} ms), fis-{} {:.4f} ({:.2f} ms) on {} -> {}/sheet.png\n",
               report["table"]["spheres_l1"].get<double>(), tableRun.gpuMs, o.samples, report["fis"]["spheres_l1"].get<double>(),
               fisRun.gpuMs, device.info().name, o.out);
}

} // namespace

void addCompareCommand(CLI::App& app) {
    auto o = std::make_shared<CompareOptions>();
    CLI::App* cmd = app.add_subcommand("compare", "Comparison sheet: reference, tap table and FIS spheres with error heat maps");
    cmd->add_option("input", o->input,
                    "Probe image: EXR or Radiance HDR, equirectangular (2:1), faces in a 6:1 strip or 1:6 column, or a 4:3 or 3:4 cross")
        ->required();
    cmd->add_option("--size", o->size, kGpuSizeHelp)->required();
    cmd->add_option("--levels", o->levels, "Output level count M (default max(1, log2 S_0))");
    cmd->add_option("--table", o->table,
                    "Tap table: a committed table's name or a table file (default: the compiled-in table for the size)");
    cmd->add_option("--samples", o->samples, fmt::format("FIS samples per texel (1 to {})", probe::kMaxSamples))->capture_default_str();
    cmd->add_option("--roughness", o->roughness,
                    fmt::format("Perceptual roughness of each sphere (1 to {} values)", probe::kMaxSheetSpheres))
        ->capture_default_str()
        ->delimiter(',');
    cmd->add_option("--cell", o->cell, fmt::format("Pixels per sphere (8 to {})", probe::kMaxSheetCell))->capture_default_str();
    cmd->add_option("--max-error", o->maxError, "Relative error shown white in the heat maps")->capture_default_str();
    cmd->add_option(
           "--repeat", o->repeat,
           fmt::format("Timed GPU runs per method (1 to {}), in turns after an untimed one; times are the median", probe::kMaxRepeat))
        ->capture_default_str();
    cmd->add_option("--sampling", o->sampling, kSamplingHelp)->capture_default_str();
    cmd->add_option("--device", o->device, kDeviceHelp);
    cmd->add_flag("--validate", o->validate, "Enable the Vulkan validation layer; any message is an error");
    cmd->add_flag("--repair-pixels", o->repairPixels,
                  "Set NaN and Inf pixels to 0 instead of refusing the file (negative pixels are always clamped to 0)");
    cmd->add_option("--out", o->out, "Output folder: sheet.png and report.json")->required();
    cmd->add_flag("--force", o->force, kForceHelp);
    cmd->add_flag("--allow-long", o->allowLong, kAllowLongHelp);
    cmd->callback([o] { runCompare(*o); });
}

} // namespace probefilter
