// probefilter sweep: what accuracy costs in time. One run on one device: for every probe and
// every method (each table of the size in --tables, FIS over samples x bias x pyramid, and over
// samples x bias on a dual-paraboloid map), the image
// L1 against the exact reference per level, the impulse-response L1 per level, and the GPU time of
// all levels and of each level's pass-2 dispatch (median of --repeat runs, interleaved over the
// methods), and the trilinear pyramid reads and the filter shader's taps or samples per output texel,
// costs that do not depend on the device (bench/shader_stats/shader_stats --sweep turns the latter into
// instructions). Writes sweep.csv, sweep.md and report.json; bench/scripts/plot-sweep draws it. With --summarize,
// summarizes a sweep.csv again without running anything.
#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "bench_commands.h"
#include "commands.h"
#include "probe/error.h"
#include "probe/fis.h"
#include "probe/impulse_error.h"
#include "probe/input_file.h"
#include "probe/json_input.h"
#include "probe/limits.h"
#include "probe/paraboloid.h"
#include "probe/probe_io.h"
#include "probe/reference.h"
#include "probe/runtime.h"
#include "probe/staged_output.h"
#include "probe/synthetic.h"
#include "probe/table_filter.h"
#include "probe/table_io.h"
#include "report.h"
#include "sweep_summary.h"

namespace probefilter {

namespace {

struct SweepOptions {
    int size = 128;
    std::vector<std::string> synthetic{"impulse-centre", "impulse-edge", "impulse-corner", "sunsky", "room", "checker"};
    std::string hdriDir;
    std::vector<int> samples{8, 16, 32, 64, 128, 256, 1024};
    std::vector<int> fisMix{8, 16, 32}; // per-level FIS: N at level 1 (probe::mixedLevelSamples)
    std::vector<double> biases{0.0, 0.5, 1.0};
    std::vector<std::string> pyramids{"bspline", "box"};
    std::vector<std::string> fisMaps{"cube", "paraboloid"}; // paraboloid: uniform counts x biases, on its own box mips
    int repeat = 5;
    int texelBudget = 384;
    std::string tables = "tables";
    std::string lobe = "ggx";
    std::string sampling = "automatic";
    std::string pyramidFormat = "auto";
    std::string device;
    std::string summarize;
    std::string out;
    bool force = false;
    bool allowLong = false;
};

struct NamedProbe {
    std::string name;
    probe::CubeImage cube;
};

std::vector<NamedProbe> sweepProbes(const SweepOptions& o) {
    std::vector<NamedProbe> probes;
    const int s = o.size, mid = s / 2;
    for (const std::string& name : o.synthetic) {
        if (name == "impulse-centre") probes.push_back({name, probe::impulseProbe(s, {4, mid, mid})});
        else if (name == "impulse-edge") probes.push_back({name, probe::impulseProbe(s, {4, s - 1, mid})});
        else if (name == "impulse-corner") probes.push_back({name, probe::impulseProbe(s, {4, s - 1, s - 1})});
        else probes.push_back({name, probe::syntheticProbe(name, s)});
    }
    if (!o.hdriDir.empty()) {
        if (!std::filesystem::is_directory(o.hdriDir)) throw probe::ProbeError(fmt::format("{}: --hdri-dir is not a folder", o.hdriDir));
        std::vector<std::filesystem::path> files;
        for (const auto& entry : std::filesystem::directory_iterator(o.hdriDir))
            if (entry.path().extension() == ".exr") files.push_back(entry.path());
        std::sort(files.begin(), files.end());
        for (const auto& file : files) {
            probe::Image image = probe::readImage(file);
            const probe::ProbeLayout layout = probe::detectLayout(image, file);
            probe::checkPixels(image, file, probe::BadPixelPolicy::repair);
            probes.push_back({file.stem().stem().string(), probe::imageToCube(image, layout, s)});
        }
    }
    return probes;
}

struct Method {
    SweepMethod description;
    probe::gpu::FilterSettings settings;
    probe::TapGenerator taps;
};

struct NamedTable {
    std::string name;
    probe::TapTable table;
};

// The glTF tables of the size, level count and lobe among the table files (*.json) of the folder, in
// name order.
std::vector<NamedTable> sweepTables(const SweepOptions& o, int levelCount, probe::Lobe lobe) {
    if (!std::filesystem::is_directory(o.tables)) throw probe::ProbeError(fmt::format("--tables {}: not a folder", o.tables));
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(o.tables))
        if (entry.path().extension() == ".json") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    std::vector<NamedTable> tables;
    for (const auto& file : files) {
        probe::TapTable table = probe::readTable(file);
        if (table.faceSize == o.size && table.levelCount == levelCount && table.mapping == probe::RoughnessMapping::gltf &&
            table.lobe == lobe)
            tables.push_back({file.stem().string(), std::move(table)});
    }
    return tables;
}

// Per output texel of the levels from firstLevel (1 where level 0 is a copy), averaged over those texels: the trilinear reads (a table's
// taps in each frame the texel blends, frames of weight 0 skipped, a mix's padding not read; FIS's samples with n.l > 0), and the taps or
// samples the filter shader's loop runs. They are the same but for a table level whose taps in use are not a multiple of four:
// table_filter.comp runs them in groups of four, the zero-weight padding included.
struct ReadCounts {
    double reads = 0.0, shaderTaps = 0.0; // per output texel
};

ReadCounts readsPerTexel(const probe::TapGenerator& taps, int size, int firstLevel, int levelCount, const probe::TapTable* table) {
    std::vector<probe::Tap> list;
    double reads = 0.0, shaderTaps = 0.0, texels = 0.0;
    for (int m = firstLevel; m < levelCount; ++m) {
        const int used = table && table->levels[m].fisSamples == 0 ? probe::tapsInUse(*table, m) : 0; // FIS reads no padding
        const double padding = used > 0 ? 4.0 * ((used + 3) / 4) / used : 1.0;
        double levelReads = 0.0;
        for (int face = 0; face < 6; ++face)
            for (int j = 0; j < size >> m; ++j)
                for (int i = 0; i < size >> m; ++i) {
                    levelReads += taps(m, {face, i, j}, list) ? static_cast<double>(list.size()) : 1.0;
                    texels += 1.0;
                }
        reads += levelReads;
        shaderTaps += levelReads * padding;
    }
    if (texels == 0.0) return {};
    return {reads / texels, shaderTaps / texels};
}

void setReads(Method& m, int size, int firstLevel, int levelCount, const probe::TapTable* table) {
    const ReadCounts reads = readsPerTexel(m.taps, size, firstLevel, levelCount, table);
    m.description.readsPerTexel = reads.reads;
    m.description.shaderTapsPerTexel = reads.shaderTaps;
}

// The level the errors and reads start from: 1 where level 0 is a copy for every method (GGX), else 0.
int firstLevel(probe::Lobe lobe, int levelCount) {
    return probe::lobeAlpha(lobe, probe::levelAlpha(probe::RoughnessMapping::gltf, 0, levelCount)) > 0.0 ? 0 : 1;
}

// The tables of the sweep's lobe ("table"); for Charlie also the GGX tables, whose levels engines
// read at the sheen roughness in its place ("ggx-levels", as Filament does), measured against Charlie.
std::vector<Method> sweepMethods(const SweepOptions& o, int levelCount, const std::vector<NamedTable>& tables,
                                 const std::vector<NamedTable>& standIns, probe::Lobe lobe) {
    std::vector<Method> methods;
    const probe::gpu::Sampling sampling = probe::gpu::parseSampling(o.sampling);
    const VkFormat pyramidFormat = probe::gpu::parsePyramidFormat(o.pyramidFormat);
    const int first = firstLevel(lobe, levelCount);
    for (const bool standIn : {false, true})
        for (const NamedTable& t : standIn ? standIns : tables) {
            Method m;
            m.description = {standIn ? "ggx-levels-" + t.name : t.name,
                             standIn ? "ggx-levels" : "table",
                             t.table.taps,
                             0.0,
                             std::string(probe::pyramidKindName(t.table.pyramid.kind)),
                             std::string(probe::tableFormName(t.table.form))};
            m.settings.method = {probe::MethodKind::table, &t.table, {}};
            m.settings.method.lobe = t.table.lobe;
            m.settings.sampling = sampling;
            m.settings.pyramidFormat = pyramidFormat;
            m.taps = probe::tableMethodTapGenerator(t.table);
            setReads(m, o.size, first, levelCount, &t.table);
            methods.push_back(std::move(m));
        }
    // FIS at one count for every level ("fis"), and the per-level mix with N at level 1 ("fis-mix").
    for (const bool mix : {false, true})
        for (const std::string& pyramid : o.pyramids)
            for (double bias : o.biases)
                for (int samples : mix ? o.fisMix : o.samples) {
                    Method m;
                    probe::FisSettings fis;
                    fis.samples = samples;
                    fis.bias = bias;
                    fis.pyramid.kind = probe::parsePyramidKind(pyramid);
                    if (mix) fis.levelSamples = probe::mixedLevelSamples(samples, levelCount);
                    m.description = {fmt::format("{}{}-bias{}-{}", mix ? "fismix" : "fis", samples, bias, pyramid),
                                     mix ? "fis-mix" : "fis",
                                     samples,
                                     bias,
                                     pyramid,
                                     ""};
                    m.settings.method = {probe::MethodKind::fis, nullptr, fis};
                    m.settings.method.lobe = lobe;
                    m.settings.sampling = sampling;
                    m.settings.pyramidFormat = pyramidFormat;
                    m.taps = probe::fisTapGenerator(o.size, levelCount, probe::RoughnessMapping::gltf, fis, lobe);
                    setReads(m, o.size, first, levelCount, nullptr);
                    methods.push_back(std::move(m));
                }
    // FIS on a dual-paraboloid map: the same samples, read from the map (its mips are box averages).
    // GGX's alone, as probe::validateMethod has it.
    for (const std::string& map : o.fisMaps) {
        if (probe::parseFisMap(map) != probe::FisMap::paraboloid || lobe != probe::Lobe::ggx) continue;
        for (double bias : o.biases)
            for (int samples : o.samples) {
                Method m;
                probe::FisSettings& fis = m.settings.method.fis;
                fis.samples = samples;
                fis.bias = bias;
                fis.map = probe::FisMap::paraboloid;
                m.description = {fmt::format("fisparaboloid{}-bias{}", samples, bias), "fis-paraboloid", samples, bias, "paraboloid", ""};
                m.settings.method.kind = probe::MethodKind::fis; // read exactly, whatever --sampling and --pyramid-format say
                m.taps = probe::fisTapGenerator(o.size, levelCount, probe::RoughnessMapping::gltf, fis);
                setReads(m, o.size, first, levelCount, nullptr);
                methods.push_back(std::move(m));
            }
    }
    return methods;
}

// The sweep's summary of `rows` into `output` (sweep.md, report.json), committed, and printed.
// pyramidFormat: empty unless hardware sampling.
void writeSummary(probe::StagedOutput& output, const std::vector<SweepRow>& rows, const std::string& name, const std::string& driver,
                  const std::string& sampling, const std::string& pyramidFormat, const SweepShape& shape) {
    const SweepSummary summary = summarizeSweep(rows, shape.firstLevel);
    // "hardware sampling, rgba32f pyramid" or "exact sampling", for the Markdown's device line.
    const std::string samplingText =
        pyramidFormat.empty() ? fmt::format("{} sampling", sampling) : fmt::format("{} sampling, {} pyramid", sampling, pyramidFormat);
    const nlohmann::json header = reportHeader("sweep");
    writeSweepMarkdown(output.file("sweep.md"), summary, rows, fmt::format("{} ({}), {}", name, driver, samplingText), shape, header);
    nlohmann::json report = sweepSummaryJson(summary, name, driver, shape);
    report.update(header);
    report["sampling"] = sampling;
    if (!pyramidFormat.empty()) report["pyramid_format"] = pyramidFormat;
    writeJson(output.file("report.json"), report);
    output.commit();
    fmt::print("{}", formatSummary(summary));
}

// Summarizes a finished sweep again (DIR/sweep.csv, and DIR/report.json for the device) into --out,
// another folder: sweep.csv, sweep.md and report.json.
void summarizeAgain(const SweepOptions& o) {
    const std::filesystem::path dir = o.summarize;
    const std::vector<SweepRow> rows = readSweepCsv(dir / "sweep.csv");
    std::string name, driver, sampling, pyramidFormat;
    SweepShape shape;
    try {
        const nlohmann::json previous = probe::parseJsonFile(probe::readTextFile(dir / "report.json"), dir / "report.json", "sweep report");
        name = previous.at("device").at("name").get<std::string>();
        driver = previous.at("device").at("driver").get<std::string>();
        sampling = previous.at("sampling").get<std::string>();
        pyramidFormat = previous.value("pyramid_format", "");
        shape.size = previous.at("face_size").get<int>();
        shape.levelCount = previous.at("level_count").get<int>();
        shape.lobe = previous.value("lobe", "ggx");
        shape.firstLevel = previous.value("first_level", 1);
    } catch (const nlohmann::json::exception&) {
        throw probe::ProbeError(
            fmt::format("{}: not a sweep report (device, sampling, face_size or level_count missing)", (dir / "report.json").string()));
    }
    probe::StagedOutput output(o.out, {dir}, o.force);
    writeSweepCsv(output.file("sweep.csv"), rows);
    writeSummary(output, rows, name, driver, sampling, pyramidFormat, shape);
}

// A method's impulse-response L1 per level over stratified texels (it does not depend on the probe).
std::vector<probe::ImpulseError> methodImpulseErrors(const SweepOptions& o, int levelCount, probe::Lobe lobe, const Method& method,
                                                     std::map<probe::PyramidKind, std::vector<probe::DownsampleOperator>>& operators) {
    const probe::PyramidSettings pyramid = method.settings.method.pyramid();
    auto& ops = operators[pyramid.kind];
    if (ops.empty()) ops = probe::pyramidOperators(o.size, pyramid);
    std::vector<probe::ImpulseError> impulse;
    const probe::FisSettings& fis = method.settings.method.fis;
    std::optional<probe::ParaboloidImpulse> paraboloid;
    if (method.settings.method.kind == probe::MethodKind::fis && fis.map == probe::FisMap::paraboloid)
        paraboloid.emplace(o.size, levelCount, probe::RoughnessMapping::gltf, fis);
    for (int m = 0; m < levelCount; ++m) {
        const std::vector<probe::WeightedTexel> texels = probe::stratifiedTexels(o.size >> m, o.texelBudget);
        // A paraboloid map's level 0 is a copy, as every method's.
        if (paraboloid && probe::levelAlpha(probe::RoughnessMapping::gltf, m, levelCount) > 0.0)
            impulse.push_back(probe::impulseError([&](const probe::Texel& t) { return paraboloid->response(m, t); }, o.size, levelCount,
                                                  probe::RoughnessMapping::gltf, lobe, m, texels));
        else impulse.push_back(probe::impulseError(method.taps, ops, o.size, levelCount, probe::RoughnessMapping::gltf, lobe, m, texels));
    }
    return impulse;
}

// GPU time does not depend on the probe's content: every method runs the first probe in each of
// --repeat rounds, so that a machine whose speed drifts during the sweep slows every method
// alike; the median over the rounds. In a round a method runs three times in a row, as in
// bench/scripts/runtime: twice timed per pass, the first to warm the GPU up, for the total of the
// second; then once timed per level (timestamps that keep a GPU from overlapping levels) for
// each level's time. Sets every row's gpuMs and levelGpuMs.
void timeMethods(const SweepOptions& o, int levelCount, const std::vector<Method>& methods,
                 const std::vector<std::unique_ptr<probe::gpu::Filter>>& filters, const probe::CubeImage& probe,
                 std::vector<SweepRow>& rows) {
    // Per method: the total, then each level's pass-2 dispatch, one per round.
    std::vector<std::vector<std::vector<double>>> runsMs(methods.size(), std::vector<std::vector<double>>(levelCount + 1));
    for (int round = 0; round < o.repeat; ++round) {
        for (std::size_t k = 0; k < methods.size(); ++k) {
            filters[k]->run(probe, 2);
            for (const probe::gpu::PassTime& t : filters[k]->timings())
                if (t.name == "total") runsMs[k][0].push_back(t.runsMs.back());
            filters[k]->run(probe, 1, probe::gpu::Timestamps::levels);
            const std::vector<probe::gpu::PassTime> levels = filters[k]->levelTimings();
            for (std::size_t m = 0; m < levels.size(); ++m) runsMs[k][m + 1].push_back(levels[m].medianMs);
        }
        printProgress("timing", static_cast<std::size_t>(round + 1), static_cast<std::size_t>(o.repeat));
    }
    for (std::size_t k = 0; k < methods.size(); ++k)
        for (SweepRow& row : rows)
            if (row.method.name == methods[k].description.name) {
                row.gpuMs = median(runsMs[k][0]);
                row.levelGpuMs = median(runsMs[k][static_cast<std::size_t>(row.level) + 1]);
            }
}

void runSweep(const SweepOptions& o) {
    if (!o.summarize.empty()) return summarizeAgain(o);
    probe::checkRepeat(o.repeat);
    for (const auto& [flag, counts] : {std::pair{"--samples", &o.samples}, std::pair{"--fis-mix", &o.fisMix}})
        for (int samples : *counts)
            if (samples < 1 || samples > probe::kMaxSamples)
                throw probe::ProbeError(fmt::format("{} {}: must be 1 to {}", flag, samples, probe::kMaxSamples));
    const int levelCount = probe::defaultLevelCount(o.size);
    probe::validateSizeAndLevels(o.size, levelCount);
    const probe::Lobe lobe = probe::parseLobe(o.lobe);
    std::vector<std::filesystem::path> inputs{o.tables};
    if (!o.hdriDir.empty()) inputs.emplace_back(o.hdriDir);
    probe::StagedOutput output(o.out, inputs, o.force);
    probe::gpu::DeviceOptions deviceOptions;
    deviceOptions.choice = o.device;
    const probe::gpu::Device device(deviceOptions);
    const std::vector<NamedProbe> probes = sweepProbes(o);
    checkReferenceTime(o.size, levelCount, probe::RoughnessMapping::gltf, lobe, probes.size(), o.allowLong);
    const std::vector<NamedTable> tables = sweepTables(o, levelCount, lobe);
    const std::vector<NamedTable> standIns =
        lobe == probe::Lobe::ggx ? std::vector<NamedTable>{} : sweepTables(o, levelCount, probe::Lobe::ggx);
    std::vector<Method> methods = sweepMethods(o, levelCount, tables, standIns, lobe);
    probe::printToStderr(fmt::format("sweep: {} probes x {} methods, {}^2, {} levels, on {}\n", probes.size(), methods.size(), o.size,
                                     levelCount, device.info().name));

    // Every method's filter first, so that settings the device refuses fail before the references run.
    std::vector<std::unique_ptr<probe::gpu::Filter>> filters;
    for (Method& method : methods) {
        method.settings.faceSize = o.size;
        method.settings.levelCount = levelCount;
        filters.push_back(std::make_unique<probe::gpu::Filter>(device, method.settings));
    }

    std::vector<probe::CubeLevels> references;
    for (std::size_t p = 0; p < probes.size(); ++p) {
        references.push_back(probe::referenceFilter(probes[p].cube, levelCount, probe::RoughnessMapping::gltf, {}, lobe));
        printProgress("reference", p + 1, probes.size());
    }

    std::vector<SweepRow> rows;
    std::map<probe::PyramidKind, std::vector<probe::DownsampleOperator>> operators;
    for (std::size_t k = 0; k < methods.size(); ++k) {
        const std::vector<probe::ImpulseError> impulse = methodImpulseErrors(o, levelCount, lobe, methods[k], operators);
        for (std::size_t p = 0; p < probes.size(); ++p) {
            const probe::CubeLevels out = filters[k]->run(probes[p].cube);
            for (int m = 0; m < levelCount; ++m)
                rows.push_back({methods[k].description, probes[p].name, m, probe::imageL1(out[m], references[p][m]), impulse[m].mean,
                                impulse[m].max, 0.0});
        }
        printProgress("methods", k + 1, methods.size());
    }
    timeMethods(o, levelCount, methods, filters, probes.front().cube, rows);

    writeSweepCsv(output.file("sweep.csv"), rows);
    const probe::gpu::Filter& first = *filters.front();
    const std::string sampling(probe::gpu::samplingName(first.sampling()));
    const std::string pyramidFormat(first.sampling() == probe::gpu::Sampling::hardware ? probe::gpu::formatName(first.pyramidFormat())
                                                                                       : "");
    const SweepShape shape{o.size, levelCount, std::string(probe::lobeName(lobe)), firstLevel(lobe, levelCount)};
    writeSummary(output, rows, device.info().name, device.info().driver, sampling, pyramidFormat, shape);
}

} // namespace

void addSweepCommand(CLI::App& app) {
    auto o = std::make_shared<SweepOptions>();
    CLI::App* cmd = app.add_subcommand("sweep", "Error against time for every table and FIS setting on a probe set (one device, one run)");
    cmd->add_option("--size", o->size, kGpuSizeHelp);
    cmd->add_option("--synthetic", o->synthetic,
                    "Generated probes: impulse-centre, impulse-edge, impulse-corner, sunsky, room, checker, sky");
    cmd->add_option("--hdri-dir", o->hdriDir, "Folder of real HDRIs (.exr) to add (scripts/fetch-hdri prints one)");
    cmd->add_option("--samples", o->samples, fmt::format("FIS sample counts (each 1 to {})", probe::kMaxSamples));
    cmd->add_option("--fis-mix", o->fisMix, "FIS per-level mixes: N at level 1, 4N at level 2, 16N from level 3 (at most 1024)");
    cmd->add_option("--fis-bias", o->biases, "FIS level biases");
    cmd->add_option("--pyramid", o->pyramids, "FIS pyramids: bspline, box");
    cmd->add_option("--fis-maps", o->fisMaps, "What FIS reads: cube (the pyramids above), paraboloid (a dual-paraboloid map)")
        ->capture_default_str();
    cmd->add_option("--repeat", o->repeat,
                    fmt::format("Timing rounds over the methods (1 to {}), on the first probe: a warm-up run, a run timed per pass and one "
                                "timed per level each round (median over the rounds)",
                                probe::kMaxRepeat));
    cmd->add_option("--texels", o->texelBudget,
                    "Stratified output texels per level for the impulse L1 (at least 1; a level with fewer measures all)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--tables", o->tables, "Folder of table files (*.json): its glTF tables of the size and lobe are swept")
        ->capture_default_str();
    cmd->add_option("--lobe", o->lobe,
                    "The lobe every method filters with and is measured against: ggx, or charlie (sheen; beside its tables and FIS, "
                    "the GGX tables' levels that engines read in its place)")
        ->capture_default_str();
    cmd->add_option("--sampling", o->sampling, kSamplingHelp)->capture_default_str();
    cmd->add_option("--pyramid-format", o->pyramidFormat,
                    "Hardware sampling's pyramid image for the tables and FIS on the cube: auto, rgba32f, rgba16f or rgb9e5")
        ->capture_default_str();
    cmd->add_option("--device", o->device, kDeviceHelp);
    cmd->add_option("--summarize", o->summarize,
                    "Run nothing: summarize the sweep in this folder (its sweep.csv) again into --out (another folder)");
    cmd->add_option("--out", o->out, "Output folder")->required();
    cmd->add_flag("--force", o->force, kForceHelp);
    cmd->add_flag("--allow-long", o->allowLong, kAllowLongHelp);
    cmd->callback([o] { runSweep(*o); });
}

} // namespace probefilter
