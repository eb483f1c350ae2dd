// probefilter filter IN... --method table|fis|reference [--lobe ggx|charlie] [--table FILE|NAME] [--samples N] --size S
//   [--levels M] [--mapping NAME] [--sampling MODE] [--pyramid-format F] [--format F] [--repeat K] [--level-times]
//   [--against-reference]
//   [--device X] --out DIR
#include <algorithm>
#include <fstream>
#include <numeric>

#include <fmt/format.h>

#include "commands.h"
#include "irradiance_output.h"
#include "probe/error.h"
#include "probe/error_measures.h"
#include "probe/input_file.h"
#include "probe/limits.h"
#include "probe/probe_io.h"
#include "probe/reference.h"
#include "probe/runtime.h"
#include "probe/staged_output.h"
#include "probe/table_io.h"
#include "probe_outputs.h"
#include "report.h"
#include "table_option.h"

namespace probefilter {

namespace {

struct FilterOptions {
    std::vector<std::string> inputs; // several: one batch, a sub-folder each
    std::string method = "table";
    std::string lobe = "ggx";
    std::string table;            // a table file (project JSON or published text) or a compiled-in table's name
    int tableTaps = 0;            // published text layout: taps per frame
    std::string tableForm;        // published text layout: const or quad
    std::vector<int> samples{32}; // one count for every level, or one per level
    double fisBias = 0.0;
    std::string fisMap = "cube";
    std::string pyramid = "bspline";
    std::string weighting = "solid-angle";
    int size = 128;
    std::optional<int> levels; // default: the mapping's list, else max(1, log2 S)
    std::string mapping;
    std::string roughness;
    std::string sampling = "automatic";
    std::string pyramidFormat = "auto";
    std::string format = "rgba32f";
    int repeat = 1;
    bool levelTimes = false;
    bool againstReference = false;
    std::string device;
    bool validate = false;
    bool repairPixels = false;
    std::string ktx2 = "none";
    bool ktx2Zstd = false;
    std::string irradiance = "none";
    std::optional<int> slices; // time slicing: the update in this many slices, one submission each
    std::string out;
    bool force = false;
    bool allowLong = false;
};

std::string probefitCommand(const probe::gpu::FilterSettings& s, const probe::PyramidSettings& pyramid) {
    return fmt::format(
        "probefit fit --size {} --levels {} --taps 8 --form quad {}{} --pyramid {} --pyramid-weighting {} --out tables/<name>", s.faceSize,
        s.levelCount, probe::mappingOptions(s.mapping),
        s.method.lobe == probe::Lobe::ggx ? "" : fmt::format(" --lobe {}", probe::lobeName(s.method.lobe)),
        probe::pyramidKindName(pyramid.kind), probe::pyramidWeightingName(pyramid.weighting));
}

// The table that --table names (a compiled-in table or a file), or else the compiled-in table for
// the settings and pyramid (quad with 8 taps preferred). Its shape is checked by the runtime.
probe::TapTable chooseTable(const FilterOptions& o, const probe::gpu::FilterSettings& s, const probe::PyramidSettings& pyramid) {
    if (!o.table.empty()) return tableOption(o.table, {o.tableTaps, o.tableForm, s.faceSize, s.levelCount, s.mapping, pyramid});
    const probe::gpu::CompiledTable* best = probe::gpu::findCompiledTable(s.faceSize, s.levelCount, s.mapping, pyramid, s.method.lobe);
    if (!best)
        throw probe::ProbeError(
            fmt::format("no compiled-in {} tap table for {}^2, {} levels, {} mapping, {} {} pyramid; make one with `{}` "
                        "and pass --table tables/<name>.json (or rebuild to compile it in)",
                        probe::lobeName(s.method.lobe), s.faceSize, s.levelCount, probe::describeRoughnessMapping(s.mapping),
                        probe::pyramidKindName(pyramid.kind), probe::pyramidWeightingName(pyramid.weighting), probefitCommand(s, pyramid)));
    return best->table;
}

nlohmann::json describeTable(const probe::TapTable& t) {
    return {{"taps_per_frame", t.taps},    {"form", std::string(probe::tableFormName(t.form))},     {"face_size", t.faceSize},
            {"level_count", t.levelCount}, {"mapping", probe::describeRoughnessMapping(t.mapping)}, {"lobe", probe::lobeName(t.lobe)},
            {"solver", t.solver}};
}

// The runtime's settings from the command line; the table, where the method is one, goes into `table`.
probe::gpu::FilterSettings filterSettings(const FilterOptions& o, const probe::PyramidSettings& pyramid, probe::TapTable& table) {
    probe::gpu::FilterSettings s;
    s.method.kind = probe::parseMethodKind(o.method);
    s.method.lobe = probe::parseLobe(o.lobe);
    s.mapping = probe::mappingFromOptions(o.mapping, o.roughness);
    s.faceSize = o.size;
    s.levelCount = probe::chooseLevelCount(o.size, o.levels, s.mapping);
    s.sampling = probe::gpu::parseSampling(o.sampling);
    s.pyramidFormat = probe::gpu::parsePyramidFormat(o.pyramidFormat);
    s.outputFormat = probe::gpu::parseFormat(o.format);
    s.method.fis.samples = o.samples.front();
    if (o.samples.size() > 1) s.method.fis.levelSamples = o.samples;
    s.method.fis.bias = o.fisBias;
    s.method.fis.map = probe::parseFisMap(o.fisMap);
    s.method.fis.pyramid = pyramid;
    if (s.method.kind == probe::MethodKind::table) {
        table = chooseTable(o, s, pyramid);
        if (!(table.pyramid == pyramid))
            throw probe::ParameterError(
                "table", fmt::format("does not fit: it was fitted over the {} {} pyramid, not {} {}",
                                     probe::pyramidKindName(table.pyramid.kind), probe::pyramidWeightingName(table.pyramid.weighting),
                                     probe::pyramidKindName(pyramid.kind), probe::pyramidWeightingName(pyramid.weighting)));
        s.method.table = &table;
    }
    probe::validateMethod(s.method, s.faceSize, s.levelCount, s.mapping);
    return s;
}

constexpr int kMaxSlices = 64;

// The slices of a sliced run and the GPU time each took (none where the queue has no timestamps).
nlohmann::json describeSlices(const std::vector<probe::gpu::Slice>& slices, const std::vector<double>& sliceMs) {
    nlohmann::json out = nlohmann::json::array();
    for (std::size_t k = 0; k < slices.size(); ++k) {
        nlohmann::json slice = {{"pyramid", slices[k].pyramid},
                                {"levels", slices[k].levels},
                                {"dispatches", slices[k].dispatches},
                                {"texel_taps", slices[k].texelTaps}};
        if (k < sliceMs.size()) slice["gpu_ms"] = sliceMs[k];
        out.push_back(slice);
    }
    return out;
}

// The report of a finished run: the settings, the device, every dispatch and the GPU times.
nlohmann::json describeRun(const FilterOptions& o, const probe::gpu::FilterSettings& s, const probe::PyramidSettings& pyramid,
                           const probe::gpu::Device& device, const probe::gpu::Filter& filter) {
    nlohmann::json report = describeLevels(s.faceSize, s.levelCount, s.mapping, s.method.lobe);
    report.update(reportHeader("filter"));
    report["method"] = std::string(probe::methodKindName(s.method.kind));
    report["sampling"] = std::string(probe::gpu::samplingName(filter.sampling()));
    report["output_format"] = std::string(probe::gpu::formatName(s.outputFormat));
    if (s.method.kind != probe::MethodKind::reference)
        report["pyramid"] = {{"kind", std::string(probe::pyramidKindName(pyramid.kind))},
                             {"weighting", std::string(probe::pyramidWeightingName(pyramid.weighting))},
                             {"format", std::string(probe::gpu::formatName(filter.pyramidFormat()))}};
    if (s.method.kind == probe::MethodKind::fis) {
        const probe::FisSettings& fis = s.method.fis;
        const nlohmann::json samples = fis.levelSamples.empty() ? nlohmann::json(fis.samples) : nlohmann::json(fis.levelSamples);
        report["fis"] = {{"samples", samples}, {"bias", fis.bias}, {"map", std::string(probe::fisMapName(fis.map))}};
    }
    if (s.method.kind == probe::MethodKind::table) {
        report["table"] = describeTable(*s.method.table);
        markHandOffs(report["levels"], *s.method.table);
    }
    report["device"] = describeDevice(device.info(), o.validate);
    report["dispatches"] = describeDispatches(filter.dispatches());
    report["barriers"] = filter.barriers();
    report["repeat"] = o.repeat;
    nlohmann::json passes = nlohmann::json::array();
    for (const probe::gpu::PassTime& p : filter.timings())
        passes.push_back({{"name", p.name}, {"gpu_ms_median", p.medianMs}, {"gpu_ms_runs", p.runsMs}});
    report["passes"] = passes;
    // Pass 2 level by level, with --level-times (filter computes every level: entry k is level k).
    const std::vector<probe::gpu::PassTime> levelTimes = filter.levelTimings();
    for (std::size_t k = 0; k < levelTimes.size(); ++k) report["levels"][k]["gpu_ms_median"] = levelTimes[k].medianMs;
    return report;
}

// The most probes one command filters as a batch (FilterSettings::batchSize): 6 layers each of the
// batch's cube-map arrays.
constexpr std::size_t kMaxBatch = 64;

// A batch's sub-folders, one per input, named by the file's stem ("sky/"); refuses two inputs of one
// stem rather than guess.
std::vector<std::string> probeFolders(const std::vector<std::string>& inputs) {
    std::vector<std::string> folders;
    for (const std::string& input : inputs) {
        const std::string folder = std::filesystem::path(input).stem().string() + "/";
        if (std::find(folders.begin(), folders.end(), folder) != folders.end())
            throw probe::ProbeError(fmt::format("{}: another input has the same name, and each input's levels go into a folder named "
                                                "after it ({}); rename one",
                                                input, folder));
        folders.push_back(folder);
    }
    return folders;
}

// One probe as the command line read it.
struct LoadedProbe {
    probe::CubeImage source;
    nlohmann::json pixels; // what --repair-pixels changed
};

// The probe's outputs beside its levels, into `folder`: its errors against the CPU reference and
// its irradiance where asked, added to `report`.
void writeProbeExtras(const FilterOptions& o, IrradianceOutput irradiance, const probe::gpu::FilterSettings& s, probe::StagedOutput& output,
                      const std::string& folder, probe::gpu::Device& device, const probe::CubeImage& source,
                      const probe::CubeLevels& levels, nlohmann::json& report) {
    if (o.againstReference) {
        const probe::CubeLevels reference = probe::referenceFilter(
            source, s.levelCount, s.mapping, [](std::size_t done, std::size_t total) { printProgress("reference", done, total); },
            s.method.lobe);
        nlohmann::json errors = nlohmann::json::array();
        for (int m = 0; m < s.levelCount; ++m) errors.push_back({{"level", m}, {"image_l1", probe::imageL1(levels[m], reference[m])}});
        report["errors_against_reference"] = errors;
    }
    if (irradiance != IrradianceOutput::none) report["irradiance"] = writeIrradiance(output, folder, irradiance, device, source).report;
}

void runFilter(const FilterOptions& o) {
    // The options that need nothing else first; then the settings, which may look for a table.
    const std::optional<probe::Ktx2Settings> ktx2 = ktx2Options(o.ktx2, o.ktx2Zstd);
    const IrradianceOutput irradiance = parseIrradianceOutput(o.irradiance);
    probe::checkRepeat(o.repeat);
    if (o.slices && (*o.slices < 1 || *o.slices > kMaxSlices))
        throw probe::ProbeError(fmt::format("--slices {}: must be 1 to {}", *o.slices, kMaxSlices));
    if (o.slices && (o.repeat != 1 || o.levelTimes))
        throw probe::ProbeError("--slices runs each slice once and times it alone: it takes neither --repeat nor --level-times");
    const bool batch = o.inputs.size() > 1;
    if (o.inputs.size() > kMaxBatch)
        throw probe::ProbeError(fmt::format("{} inputs: one command filters at most {} probes as a batch", o.inputs.size(), kMaxBatch));
    if (batch && (o.slices || o.levelTimes))
        throw probe::ProbeError("several inputs run as one batch, timed as a whole: --slices and --level-times take one input");
    const std::vector<std::string> folders = batch ? probeFolders(o.inputs) : std::vector<std::string>{""};
    const probe::PyramidSettings pyramid{probe::parsePyramidKind(o.pyramid), probe::parsePyramidWeighting(o.weighting)};
    probe::TapTable table;
    probe::gpu::FilterSettings s = filterSettings(o, pyramid, table);
    if (batch && (s.method.kind == probe::MethodKind::reference ||
                  (s.method.kind == probe::MethodKind::fis && s.method.fis.map == probe::FisMap::paraboloid)))
        throw probe::ProbeError(fmt::format("several inputs run as one batch, and --method {} filters one probe at a time: give one input",
                                            s.method.kind == probe::MethodKind::reference ? "reference" : "fis --fis-map paraboloid"));
    if (batch) s.batchSize = int(o.inputs.size());
    std::vector<std::filesystem::path> inputs(o.inputs.begin(), o.inputs.end());
    if (!o.table.empty() && std::filesystem::exists(o.table)) inputs.emplace_back(o.table);
    probe::StagedOutput output(o.out, inputs, o.force);
    if (o.againstReference) checkReferenceTime(s.faceSize, s.levelCount, s.mapping, s.method.lobe, o.inputs.size(), o.allowLong);
    probe::gpu::DeviceOptions deviceOptions;
    deviceOptions.choice = o.device;
    deviceOptions.validation = o.validate;
    probe::gpu::Device device(deviceOptions);
    probe::gpu::Filter::checkLimits(device, s); // before the probes are read: at the pixel limit that takes 25 s and 1.5 GiB
    std::vector<LoadedProbe> probes;
    for (const std::string& input : o.inputs) {
        probe::PixelRepairs repairs;
        probe::CubeImage source =
            probe::loadProbe(input, o.size, o.repairPixels ? probe::BadPixelPolicy::repair : probe::BadPixelPolicy::refuse, repairs);
        probes.push_back({std::move(source), reportPixelRepairs(input, repairs)});
    }
    probe::gpu::Filter filter(device, s);
    const std::vector<probe::gpu::Slice> slices = o.slices ? filter.slices(*o.slices) : std::vector<probe::gpu::Slice>{};
    std::vector<double> sliceMs;
    std::vector<probe::CubeLevels> levels;
    if (batch) {
        std::vector<probe::CubeImage> sources;
        for (const LoadedProbe& p : probes) sources.push_back(p.source);
        levels = filter.run(sources, o.repeat);
    } else {
        const probe::CubeImage& source = probes.front().source;
        levels.push_back(
            o.slices ? filter.run(source, slices, sliceMs)
                     : filter.run(source, o.repeat, o.levelTimes ? probe::gpu::Timestamps::levels : probe::gpu::Timestamps::passes));
    }
    const std::vector<std::string> messages = device.validationMessages();
    if (!messages.empty())
        throw probe::ProbeError(
            fmt::format("the Vulkan validation layer reported {} message(s); the first: {}", messages.size(), messages.front()));

    nlohmann::json report = describeRun(o, s, pyramid, device, filter);
    if (o.slices) {
        report.erase("passes");
        report.erase("dispatches");
        report.erase("barriers");
        report["slices"] = describeSlices(slices, sliceMs);
    }
    if (batch) {
        // The dispatches above filter every probe of the batch.
        report["batch"] = {{"probes", probes.size()}, {"dispatches", filter.dispatches().size()}, {"barriers", filter.barriers()}};
        report["probes"] = nlohmann::json::array();
    }
    for (std::size_t p = 0; p < probes.size(); ++p) {
        nlohmann::json entry = {{"input", o.inputs[p]}, {"input_pixels", probes[p].pixels}};
        if (batch) entry["folder"] = folders[p];
        writeProbeExtras(o, irradiance, s, output, folders[p], device, probes[p].source, levels[p], entry);
        writeFilteredProbe(output, folders[p], levels[p], s.mapping, ktx2, &device, entry);
        if (batch) report["probes"].push_back(entry);
        else report.update(entry);
    }
    writeJson(output.file("report.json"), report);
    output.commit();

    double total = 0.0;
    for (const probe::gpu::PassTime& p : filter.timings())
        if (p.name == "total") total = p.medianMs;
    if (o.slices) total = std::accumulate(sliceMs.begin(), sliceMs.end(), 0.0);
    const probe::gpu::DeviceInfo& info = device.info();
    const std::string timing = o.slices ? fmt::format("{} slices", slices.size())
                               : batch  ? fmt::format("{} probes in one recording, median of {}", probes.size(), o.repeat)
                                        : fmt::format("median of {}", o.repeat);
    fmt::print("filter: {} ({} sampling) on {} ({}): {} levels of {}^2, GPU {:.3f} ms ({}) -> {}\n", o.method,
               probe::gpu::samplingName(filter.sampling()), info.name, info.driver, s.levelCount, s.faceSize, total, timing, o.out);
}

} // namespace

void addFilterCommand(CLI::App& app) {
    auto o = std::make_shared<FilterOptions>();
    CLI::App* cmd =
        app.add_subcommand("filter", "Filter a probe on a Vulkan device: tap table, filtered importance sampling or the exact reference");
    cmd->add_option(
           "inputs", o->inputs,
           fmt::format("Probe images: {}; several (at most {}) are filtered as one batch, one recording, each into a folder of --out "
                       "named after the file",
                       probe::kProbeImageKinds, kMaxBatch))
        ->required();
    cmd->add_option("--method", o->method, "table, fis or reference")->capture_default_str();
    cmd->add_option("--lobe", o->lobe, kLobeHelp)->capture_default_str();
    cmd->add_option(
        "--table", o->table,
        "Tap table: a committed table's name (tables/<name>.json), a table file (probefit's JSON) or the published text layout");
    cmd->add_option("--table-taps", o->tableTaps, "Published text layout: taps per frame");
    cmd->add_option("--table-form", o->tableForm, "Published text layout: const or quad");
    cmd->add_option(
           "--samples", o->samples,
           fmt::format("fis: samples per output texel (1 to {}): one count, or one per output level (level 0 first)", probe::kMaxSamples))
        ->capture_default_str();
    cmd->add_option("--fis-map", o->fisMap,
                    "fis: what the samples read: the cube pyramid, or a dual-paraboloid map with its own mips (Krivanek & Colbert as "
                    "published; exact sampling)")
        ->capture_default_str();
    cmd->add_option("--fis-bias", o->fisBias,
                    fmt::format("fis: added to each sample's pyramid level (-{0} to {0}; 0 is the accurate setting, Filament uses 1)",
                                probe::kMaxFisBias))
        ->capture_default_str();
    cmd->add_option("--pyramid", o->pyramid, "Pass 1 pyramid: bspline or box")->capture_default_str();
    cmd->add_option("--pyramid-weighting", o->weighting, "Pass 1 Jacobian weighting: solid-angle or inverse-solid-angle")
        ->capture_default_str();
    cmd->add_option("--size", o->size, kGpuSizeHelp)->required();
    cmd->add_option("--levels", o->levels, kLevelsHelp);
    cmd->add_option("--mapping", o->mapping, kMappingHelp);
    cmd->add_option("--roughness", o->roughness, kRoughnessHelp);
    cmd->add_option("--sampling", o->sampling, kSamplingHelp)->capture_default_str();
    cmd->add_option("--pyramid-format", o->pyramidFormat,
                    "Hardware sampling's pyramid image: rgba16f (half the bytes the sampler reads; a probe brighter than "
                    "65504 is filtered scaled down by a power of two), rgba32f, rgb9e5 (a quarter of rgba32f's bytes, a 9-bit "
                    "mantissa per channel under a shared exponent, no negative values), or auto (rgba16f where the device can "
                    "filter and store it)")
        ->capture_default_str();
    cmd->add_option("--format", o->format,
                    "The GPU's output cube format, which the written levels keep: rgba32f, rgba16f (what engines use) or b10g11r11")
        ->capture_default_str();
    cmd->add_option("--repeat", o->repeat, fmt::format("Run the passes K times (1 to {}); GPU times are the median", probe::kMaxRepeat))
        ->capture_default_str();
    cmd->add_flag("--level-times", o->levelTimes,
                  "Also time each level's pass-2 dispatch alone (a timestamp after each level: on a GPU the levels then "
                  "run one after another, so pass 2 takes longer)");
    cmd->add_flag("--against-reference", o->againstReference, "Also run the CPU reference and report the image L1 error per level");
    cmd->add_option("--device", o->device, kDeviceHelp);
    cmd->add_flag("--validate", o->validate, "Enable the Vulkan validation layer; any message is an error");
    cmd->add_flag("--repair-pixels", o->repairPixels,
                  "Set NaN and Inf pixels to 0 instead of refusing the file (negative pixels are always clamped to 0)");
    cmd->add_option(
           "--ktx2", o->ktx2,
           "Also write probe.ktx2: none, rgba16f, rgba32f, rgb9e5 (shared exponent, 4 bytes a texel) or bc6h (BC6H blocks encoded on "
           "the Vulkan device, 1 byte a texel)")
        ->capture_default_str();
    cmd->add_flag("--ktx2-zstd", o->ktx2Zstd, "Store probe.ktx2's levels compressed with Zstandard (KTX2 supercompression)");
    cmd->add_option("--irradiance", o->irradiance,
                    "Also write the Lambertian irradiance: none, sh (9 coefficients, on the device; irradiance_sh.exr), cube (the "
                    "exact cosine convolution, 32^2, on the CPU; irradiance.exr) or both (and SH's error against the cube)")
        ->capture_default_str();
    cmd->add_option("--slices", o->slices,
                    fmt::format("Time slicing: run the update as N slices (1 to {}), one submission each, and report each "
                                "slice's dispatches, texel-taps and GPU time",
                                kMaxSlices));
    cmd->add_option("--out", o->out,
                    "Output folder: level_<m>.exr, preview.png and report.json (a batch: <input>/level_<m>.exr and <input>/preview.png "
                    "for each input, and one report.json)")
        ->required();
    cmd->add_flag("--force", o->force, kForceHelp);
    cmd->add_flag("--allow-long", o->allowLong, "With --against-reference: " + std::string(kAllowLongHelp));
    cmd->callback([o] { runFilter(*o); });
}

} // namespace probefilter
