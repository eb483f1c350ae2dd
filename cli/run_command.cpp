// probefilter run SCENE.json --out DIR [--device X] [--validate] [--repair-pixels]: runs exactly the scene's plan
// (probe/plan.h) on a Vulkan device. Per probe, in DIR/<probe>/: level_<m>.exr of the levels it
// computed, the SH irradiance (irradiance_sh.exr and its coefficients) and the irradiance cube
// (irradiance.exr) as the plan asks, sheen_level_<m>.exr of the Charlie levels, probe.ktx2 (and
// sheen.ktx2) and spheres.png when the scene asks; DIR/dfg.exr, DIR/sheen.exr; DIR/report.json with
// the passes it ran, each with its GPU dispatches.
#include <algorithm>

#include <fmt/format.h>

#include "commands.h"
#include "irradiance_output.h"
#include "probe/dfg.h"
#include "probe/error.h"
#include "probe/plan.h"
#include "probe/probe_io.h"
#include "probe/sh.h"
#include "probe/sheen.h"
#include "probe/staged_output.h"
#include "probe_outputs.h"
#include "report.h"
#include "scene_taps.h"
#include "spheres.h"

namespace probefilter {

namespace {

using nlohmann::json;

struct RunOptions {
    std::string scene;
    std::string out;
    bool force = false;
    std::string sampling = "automatic";
    std::string device;
    bool validate = false;
    bool repairPixels = false;
};

constexpr int kSphereCell = 192; // pixels per sphere in spheres.png

// What one probe's passes made (kept for the spheres when the scene asks for them).
struct ProbeResult {
    const probe::SceneProbe* probe = nullptr;
    probe::CubeImage source;
    probe::CubeLevels levels; // one entry per output level; empty where not computed
    probe::CubeLevels sheen;  // the Charlie levels, as `levels`
    probe::ShCoefficients irradiance{};
};

// One Filter's share of a probe's plan: its GGX levels, or its Charlie (sheen) levels.
struct PlannedLevels {
    probe::FilterMethod method; // its table is set by filterSettings
    const std::vector<int>& levels;
    const std::vector<std::vector<std::string>>& readers;
    const std::vector<probe::MethodKind>& methods; // per entry of `levels`
    int pyramidDepth;
    bool sheen;

    static PlannedLevels ggx(const probe::SceneProbe& p, const probe::ProbePlan& plan) {
        return {p.method, plan.computedLevels, plan.levelReaders, plan.levelMethods, plan.pyramidLevels, false};
    }
    static PlannedLevels charlie(const probe::SceneProbe& p, const probe::ProbePlan& plan) {
        return {probe::sheenMethod(p, plan.sheenMethod == probe::MethodKind::table),
                plan.sheenLevels,
                plan.sheenReaders,
                plan.sheenLevelMethods,
                plan.sheenPyramidLevels,
                true};
    }
};

class SceneRun {
public:
    SceneRun(const RunOptions& options, const probe::Scene& scene, probe::StagedOutput& output, const probe::gpu::Device& device)
        : options_(options), scene_(scene), output_(output), device_(device) {}

    // Every probe's filter settings checked against the device before any probe is read.
    void checkLimits(const probe::Plan& plan) const {
        for (std::size_t k = 0; k < scene_.probes.size(); ++k)
            for (const PlannedLevels& set :
                 {PlannedLevels::ggx(scene_.probes[k], plan.probes[k]), PlannedLevels::charlie(scene_.probes[k], plan.probes[k])})
                if (!set.levels.empty()) {
                    probe::TapTable table;
                    probe::gpu::Filter::checkLimits(device_, filterSettings(scene_.probes[k], set, table));
                }
    }

    // The passes of one probe's plan; appends to the report.
    void runProbe(const probe::SceneProbe& p, const probe::ProbePlan& plan) {
        const probe::BadPixelPolicy policy = options_.repairPixels ? probe::BadPixelPolicy::repair : probe::BadPixelPolicy::refuse;
        probe::PixelRepairs repairs;
        ProbeResult result{&p,
                           probe::loadProbe(p.image, p.faceSize, policy, repairs),
                           probe::CubeLevels(p.levelCount),
                           probe::CubeLevels(p.levelCount),
                           {}};
        recordPass(probe::loadPass(p.name), "cpu");
        json entry = {{"name", p.name},
                      {"image", p.image.string()},
                      {"face_size", p.faceSize},
                      {"level_count", p.levelCount},
                      {"mapping", probe::describeRoughnessMapping(p.mapping)},
                      {"method", std::string(probe::methodKindName(p.method.kind))},
                      {"input_pixels", reportPixelRepairs(p.image, repairs)}};
        if (!plan.computedLevels.empty()) filterLevels(p, PlannedLevels::ggx(p, plan), result.source, result.levels, entry);
        if (plan.shIrradiance || plan.irradianceCube) writeProbeIrradiance(p, plan, result, entry);
        if (!plan.sheenLevels.empty()) {
            entry["sheen"] = {{"method", std::string(probe::methodKindName(plan.sheenMethod))}, {"lobe", "charlie"}};
            filterLevels(p, PlannedLevels::charlie(p, plan), result.source, result.sheen, entry["sheen"]);
        }
        if (scene_.outputs.ktx2 && !plan.computedLevels.empty())
            entry["ktx2"] = writeProbeKtx2(output_, p.name + "/probe.ktx2", result.levels, p.mapping, *scene_.outputs.ktx2, &device_);
        if (scene_.outputs.ktx2 && !plan.sheenLevels.empty())
            entry["sheen"]["ktx2"] =
                writeProbeKtx2(output_, p.name + "/sheen.ktx2", result.sheen, p.mapping, *scene_.outputs.ktx2, &device_);
        probes_.push_back(std::move(entry));
        // Kept for the spheres alone, so that a scene of many large probes without them holds one
        // probe's images at a time.
        if (scene_.outputs.spheres) results_.push_back(std::move(result));
    }

    void makeDfgTable() {
        dfg_ = probe::dfgTable(probe::kDfgTableSize, probe::kDfgTableSamples);
        writeLookupTable(*dfg_, "dfg.exr", probe::kDfgPass, "dfg", probe::kDfgTableSamples, probe::kDfgConvention);
    }

    void makeSheenTable() {
        sheenTable_ = probe::sheenTable(probe::kSheenTableSize, probe::kSheenTableSamples);
        writeLookupTable(*sheenTable_, "sheen.exr", probe::kSheenTablePass, "sheen_table", probe::kSheenTableSamples,
                         probe::kSheenConvention);
    }

    // spheres.png per probe: its materials, lit by what the plan computed.
    void renderSpheres() {
        for (std::size_t k = 0; k < results_.size(); ++k) {
            const ProbeResult& r = results_[k];
            probe::gpu::SphereScene s;
            s.prefiltered = &r.levels;
            s.background = &r.source;
            s.irradiance = r.irradiance;
            s.dfg = dfg_ ? &*dfg_ : nullptr;
            s.sheen = &r.sheen;
            s.sheenTable = sheenTable_ ? &*sheenTable_ : nullptr;
            s.cellSize = kSphereCell;
            json names = json::array();
            for (const probe::SceneMaterial& m : scene_.materials)
                if (m.probe == r.probe->name) {
                    s.materials.push_back(sphereMaterial(m, r.probe->mapping, r.probe->levelCount));
                    names.push_back(m.name);
                }
            const std::string file = r.probe->name + "/spheres.png";
            writeSpheres(output_.file(file), device_, s);
            probes_[k]["spheres"] = {{"file", file}, {"materials", names}};
        }
    }

    void finish() {
        report_.update(reportHeader("run"));
        report_["scene"] = options_.scene;
        report_["device"] = describeDevice(device_.info(), options_.validate);
        report_["probes"] = probes_;
        report_["dispatches"] = ran_;
        writeJson(output_.file("report.json"), report_);
    }

    std::size_t passCount() const { return ran_.size(); }

private:
    void recordPass(const std::string& name, const char* on, json dispatches = json::array()) {
        ran_.push_back({{"pass", name}, {"on", on}, {"gpu_dispatches", std::move(dispatches)}});
    }

    // A lookup table into DIR/file, its pass and its report entry under `key`.
    void writeLookupTable(const probe::Image& table, const std::string& file, const char* pass, const char* key, int samples,
                          const char* convention) {
        probe::writeExr(output_.file(file), table);
        recordPass(pass, "cpu");
        report_[key] = {{"file", file}, {"size", table.width}, {"samples", samples}, {"convention", convention}};
    }

    // The planned levels over the planned pyramid depth; `table` holds the probe's table for them.
    probe::gpu::FilterSettings filterSettings(const probe::SceneProbe& p, const PlannedLevels& set, probe::TapTable& table) const {
        probe::gpu::FilterSettings s;
        s.method = set.method;
        s.faceSize = p.faceSize;
        s.levelCount = p.levelCount;
        s.mapping = p.mapping;
        s.sampling = probe::gpu::parseSampling(options_.sampling);
        s.computedLevels = set.levels;
        s.pyramidDepth = set.pyramidDepth;
        if (set.method.kind == probe::MethodKind::table) {
            probe::SceneProbe withLobe = p;
            withLobe.method.lobe = set.method.lobe;
            table = sceneProbeTable(scene_, withLobe);
            s.method.table = &table;
        }
        return s;
    }

    // The planned levels over the planned pyramid depth into `levels`, their files and report in
    // `entry`; the passes recorded are those its dispatches ran.
    void filterLevels(const probe::SceneProbe& p, const PlannedLevels& set, const probe::CubeImage& source, probe::CubeLevels& levels,
                      json& entry) {
        probe::TapTable table;
        const probe::gpu::FilterSettings settings = filterSettings(p, set, table);
        probe::gpu::Filter filter(device_, settings);
        levels = filter.run(source, 1, probe::gpu::Timestamps::levels);

        std::vector<probe::gpu::Dispatch> pyramid, passes;
        for (const probe::gpu::Dispatch& d : filter.dispatches()) (d.pass == "pyramid" ? pyramid : passes).push_back(d);
        if (!pyramid.empty())
            recordPass(set.sheen ? probe::sheenPyramidPass(p.name, pyramid.back().level) : probe::pyramidPass(p.name, pyramid.back().level),
                       "gpu", describeDispatches(pyramid));
        // Named by what ran: the method's pass, or FIS at a level the table hands to it.
        for (const probe::gpu::Dispatch& d : passes) {
            const probe::MethodKind ran = probe::parseMethodKind(d.pass);
            recordPass(set.sheen ? probe::sheenLevelPass(p.name, d.level, ran) : probe::levelPass(p.name, d.level, ran), "gpu",
                       describeDispatches({d}));
        }

        json written = json::array();
        const std::vector<probe::gpu::PassTime> levelTimes = filter.levelTimings(); // set.levels' order
        for (std::size_t k = 0; k < set.levels.size(); ++k) {
            const int m = set.levels[k];
            json level = {{"level", m},
                          {"face_size", p.faceSize >> m},
                          {"roughness", probe::levelRoughness(p.mapping, m, p.levelCount)},
                          {"alpha", probe::lobeAlpha(set.method.lobe, probe::levelAlpha(p.mapping, m, p.levelCount))},
                          {"method", std::string(probe::methodKindName(set.methods[k]))},
                          {"read_by", set.readers[k]}};
            if (k < levelTimes.size()) level["gpu_ms"] = levelTimes[k].medianMs;
            if (scene_.outputs.exr) {
                const std::string file = p.name + "/" + (set.sheen ? "sheen_" : "") + probe::levelFileName(m);
                probe::writeExr(output_.file(file), probe::cubeToStrip(levels[m]));
                level["file"] = file;
            }
            written.push_back(std::move(level));
        }
        entry["levels"] = std::move(written);
        entry["pyramid_depth"] = set.pyramidDepth;
        if (set.method.kind == probe::MethodKind::fis) entry["fis_samples"] = set.method.fis.samples;
        entry["sampling"] = std::string(probe::gpu::samplingName(filter.sampling()));
        entry["gpu_ms"] = medianTimes(filter.timings());
    }

    // The irradiance the plan asks for, into the probe's folder (irradiance_output.h).
    void writeProbeIrradiance(const probe::SceneProbe& p, const probe::ProbePlan& plan, ProbeResult& result, json& entry) {
        const IrradianceOutput which = plan.shIrradiance && plan.irradianceCube ? IrradianceOutput::both
                                       : plan.shIrradiance                      ? IrradianceOutput::sh
                                                                                : IrradianceOutput::cube;
        const IrradianceResult irradiance = writeIrradiance(output_, p.name + "/", which, device_, result.source);
        result.irradiance = irradiance.sh;
        if (plan.shIrradiance) recordPass(probe::irradiancePass(p.name), "gpu", describeDispatches(irradiance.shDispatches));
        if (plan.irradianceCube) recordPass(probe::irradianceCubePass(p.name), "cpu");
        entry["irradiance"] = irradiance.report;
    }

    const RunOptions& options_;
    const probe::Scene& scene_;
    probe::StagedOutput& output_;
    const probe::gpu::Device& device_;
    std::vector<ProbeResult> results_;
    std::optional<probe::Image> dfg_, sheenTable_;
    json probes_ = json::array();
    json ran_ = json::array();
    json report_ = json::object();
};

void runScene(const RunOptions& o) {
    const probe::Scene scene = probe::readScene(o.scene);
    const probe::Plan plan = probe::makePlan(
        scene, [&](const probe::SceneProbe& p) { return sceneProbeTaps(scene, p); }, hasCharlieTable);
    std::vector<std::filesystem::path> inputs{o.scene};
    for (const probe::SceneProbe& p : scene.probes) {
        inputs.push_back(p.image);
        if (p.table) inputs.push_back(*p.table);
    }
    probe::StagedOutput output(o.out, inputs, o.force);
    probe::gpu::DeviceOptions deviceOptions;
    deviceOptions.choice = o.device;
    deviceOptions.validation = o.validate;
    const probe::gpu::Device device(deviceOptions);

    SceneRun run(o, scene, output, device);
    run.checkLimits(plan);
    for (std::size_t k = 0; k < scene.probes.size(); ++k)
        if (plan.probes[k].used()) run.runProbe(scene.probes[k], plan.probes[k]);
    if (plan.dfgTable) run.makeDfgTable();
    if (plan.sheenTable) run.makeSheenTable();
    if (scene.outputs.spheres) run.renderSpheres();
    const std::vector<std::string> messages = device.validationMessages();
    if (!messages.empty())
        throw probe::ProbeError(
            fmt::format("the Vulkan validation layer reported {} message(s); the first: {}", messages.size(), messages.front()));
    run.finish();
    output.commit();
    fmt::print("run: {} pass(es) of {} on {} -> {}\n", run.passCount(), o.scene, device.info().name, o.out);
}

} // namespace

void addRunCommand(CLI::App& app) {
    auto o = std::make_shared<RunOptions>();
    CLI::App* cmd = app.add_subcommand("run", "Run exactly the passes a scene calls for (see `plan`) and write what they make");
    cmd->add_option("scene", o->scene, "Scene file (JSON)")->required();
    cmd->add_option("--out", o->out,
                    "Output folder: <probe>/level_<m>.exr, irradiance_sh.exr, irradiance.exr, sheen_level_<m>.exr, probe.ktx2, sheen.ktx2, "
                    "spheres.png; dfg.exr; sheen.exr; report.json")
        ->required();
    cmd->add_flag("--force", o->force, kForceHelp);
    cmd->add_option("--sampling", o->sampling, kSamplingHelp)->capture_default_str();
    cmd->add_option("--device", o->device, kDeviceHelp);
    cmd->add_flag("--validate", o->validate, "Enable the Vulkan validation layer; any message is an error");
    cmd->add_flag("--repair-pixels", o->repairPixels,
                  "Set NaN and Inf probe pixels to 0 instead of refusing the file (negative pixels are always clamped to 0)");
    cmd->callback([o] { runScene(*o); });
}

} // namespace probefilter
