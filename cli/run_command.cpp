// probefilter run SCENE.json --out DIR [--device X] [--validate] [--repair-pixels]: runs exactly the scene's plan
// (probe/plan.h) on a Vulkan device. Per probe, in DIR/<probe>/: level_<m>.exr of the levels it
// computed, the SH irradiance (irradiance_sh.exr and its coefficients) and the irradiance cube
// (irradiance.exr) as the plan asks, sheen_level_<m>.exr of the Charlie levels, probe.ktx2 (and
// sheen.ktx2) and spheres.png when the scene asks; DIR/dfg.exr, DIR/sheen.exr; DIR/report.json with
// the passes it ran, each with its GPU dispatches.
#include <algorithm>
#include <map>

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

// Whether two probes' filters are the same: face size, levels, mapping, method and table, and the
// levels and pyramid their plans compute, GGX and sheen.
bool sameFilters(const probe::SceneProbe& a, const probe::ProbePlan& pa, const probe::SceneProbe& b, const probe::ProbePlan& pb) {
    const probe::FisSettings &fa = a.method.fis, &fb = b.method.fis;
    return a.faceSize == b.faceSize && a.levelCount == b.levelCount && a.mapping == b.mapping && a.method.kind == b.method.kind &&
           a.method.lobe == b.method.lobe && a.table == b.table && fa.samples == fb.samples && fa.bias == fb.bias &&
           fa.pyramid == fb.pyramid && fa.levelSamples == fb.levelSamples && fa.map == fb.map && pa.computedLevels == pb.computedLevels &&
           pa.levelMethods == pb.levelMethods && pa.pyramidLevels == pb.pyramidLevels && pa.sheenMethod == pb.sheenMethod &&
           pa.sheenLevels == pb.sheenLevels && pa.sheenLevelMethods == pb.sheenLevelMethods &&
           pa.sheenPyramidLevels == pb.sheenPyramidLevels;
}

// The probes that compute anything, in batches of the same filters (one Filter, one recording each:
// FilterSettings::batchSize), in the order of their first probes. A batch's sources stay within
// kBatchTexels: ten 128^2 probes, two 256^2 ones, and a larger probe alone, so that batches pay off
// where fixed costs dominate (small probes) and a scene of large probes holds one probe's images at a
// time; and within kBatchProbes, whose 6 layers each every Vulkan device's 256 array layers hold.
constexpr std::size_t kBatchTexels = std::size_t{1} << 20;
constexpr std::size_t kBatchProbes = 42;
std::vector<std::vector<std::size_t>> batches(const probe::Scene& scene, const probe::Plan& plan) {
    std::vector<std::vector<std::size_t>> list;
    std::vector<std::size_t> texels;
    for (std::size_t k = 0; k < scene.probes.size(); ++k) {
        if (!plan.probes[k].used()) continue;
        const std::size_t size = probe::texelCount(scene.probes[k].faceSize);
        auto joins = [&](std::size_t g) {
            const std::size_t f = list[g].front();
            return sameFilters(scene.probes[f], plan.probes[f], scene.probes[k], plan.probes[k]) && texels[g] + size <= kBatchTexels &&
                   list[g].size() < kBatchProbes;
        };
        std::size_t g = 0;
        while (g < list.size() && !joins(g)) ++g;
        if (g == list.size()) {
            list.emplace_back();
            texels.push_back(0);
        }
        list[g].push_back(k);
        texels[g] += size;
    }
    return list;
}

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

    // The passes of a batch's plans (batches(): probes whose filters are the same), each probe's
    // passes recorded in its plan's order; appends to the report.
    void runBatch(const probe::Plan& plan, const std::vector<std::size_t>& batch) {
        const probe::BadPixelPolicy policy = options_.repairPixels ? probe::BadPixelPolicy::repair : probe::BadPixelPolicy::refuse;
        std::vector<ProbeResult> results;
        std::vector<json> entries;
        for (const std::size_t k : batch) {
            const probe::SceneProbe& p = scene_.probes[k];
            probe::PixelRepairs repairs;
            results.push_back({&p,
                               probe::loadProbe(p.image, p.faceSize, policy, repairs),
                               probe::CubeLevels(p.levelCount),
                               probe::CubeLevels(p.levelCount),
                               {}});
            entries.push_back({{"name", p.name},
                               {"image", p.image.string()},
                               {"face_size", p.faceSize},
                               {"level_count", p.levelCount},
                               {"mapping", probe::describeRoughnessMapping(p.mapping)},
                               {"method", std::string(probe::methodKindName(p.method.kind))},
                               {"input_pixels", reportPixelRepairs(p.image, repairs)}});
        }
        const probe::SceneProbe& first = scene_.probes[batch.front()];
        const probe::ProbePlan& firstPlan = plan.probes[batch.front()];
        std::vector<json> ggx(batch.size(), json::array()), sheen(batch.size(), json::array());
        if (!firstPlan.computedLevels.empty())
            filterLevels(first, PlannedLevels::ggx(first, firstPlan), results, &ProbeResult::levels, entries, ggx);
        if (!firstPlan.sheenLevels.empty()) {
            std::vector<json> sheenEntries(batch.size(),
                                           {{"method", std::string(probe::methodKindName(firstPlan.sheenMethod))}, {"lobe", "charlie"}});
            filterLevels(first, PlannedLevels::charlie(first, firstPlan), results, &ProbeResult::sheen, sheenEntries, sheen);
            for (std::size_t b = 0; b < batch.size(); ++b) entries[b]["sheen"] = std::move(sheenEntries[b]);
        }
        for (std::size_t b = 0; b < batch.size(); ++b) {
            const probe::SceneProbe& p = scene_.probes[batch[b]];
            const probe::ProbePlan& probePlan = plan.probes[batch[b]];
            ProbeResult& result = results[b];
            json& entry = entries[b];
            json& ran = probeRan_[batch[b]];
            ran.push_back(pass(probe::loadPass(p.name), "cpu"));
            for (json& done : ggx[b]) ran.push_back(std::move(done));
            if (probePlan.shIrradiance || probePlan.irradianceCube) writeProbeIrradiance(p, probePlan, result, entry, ran);
            for (json& done : sheen[b]) ran.push_back(std::move(done));
            if (scene_.outputs.ktx2 && !probePlan.computedLevels.empty())
                entry["ktx2"] = writeProbeKtx2(output_, p.name + "/probe.ktx2", result.levels, p.mapping, *scene_.outputs.ktx2, &device_);
            if (scene_.outputs.ktx2 && !probePlan.sheenLevels.empty())
                entry["sheen"]["ktx2"] =
                    writeProbeKtx2(output_, p.name + "/sheen.ktx2", result.sheen, p.mapping, *scene_.outputs.ktx2, &device_);
            probes_.push_back(std::move(entry));
            probeOrder_.push_back(batch[b]);
            // Kept for the spheres alone, so that a scene of many large probes without them holds one
            // batch's images at a time.
            if (scene_.outputs.spheres) results_.push_back(std::move(result));
        }
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
        // Probes and their passes in the scene's order, as the plan lists them, whatever the batches.
        std::vector<std::size_t> byScene(probes_.size());
        for (std::size_t k = 0; k < byScene.size(); ++k) byScene[k] = k;
        std::ranges::sort(byScene, {}, [&](std::size_t k) { return probeOrder_[k]; });
        json probes = json::array(), ran = json::array();
        for (const std::size_t k : byScene) probes.push_back(probes_[k]);
        for (auto& [index, passes] : probeRan_)
            for (json& done : passes) ran.push_back(std::move(done));
        for (json& done : ran_) ran.push_back(std::move(done));
        ran_ = std::move(ran);
        report_["probes"] = probes;
        report_["dispatches"] = ran_;
        writeJson(output_.file("report.json"), report_);
    }

    std::size_t passCount() const { return ran_.size(); }

private:
    static json pass(const std::string& name, const char* on, json dispatches = json::array()) {
        return {{"pass", name}, {"on", on}, {"gpu_dispatches", std::move(dispatches)}};
    }
    void recordPass(const std::string& name, const char* on, json dispatches = json::array()) {
        ran_.push_back(pass(name, on, std::move(dispatches)));
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

    // The planned levels over the planned pyramid depth of every probe of a batch (one Filter, one
    // submission; a probe alone is timed per level) into each result's `levels`, their files and
    // report in `entries`, and the passes its dispatches ran in `passes`, per probe.
    void filterLevels(const probe::SceneProbe& p, const PlannedLevels& set, std::vector<ProbeResult>& results,
                      probe::CubeLevels ProbeResult::*levels, std::vector<json>& entries, std::vector<json>& passes) {
        probe::TapTable table;
        probe::gpu::FilterSettings settings = filterSettings(p, set, table);
        const std::size_t count = results.size();
        settings.batchSize = int(count);
        probe::gpu::Filter filter(device_, settings);
        if (count == 1) {
            results[0].*levels = filter.run(results[0].source, 1, probe::gpu::Timestamps::levels);
        } else {
            std::vector<probe::CubeImage> sources;
            for (const ProbeResult& r : results) sources.push_back(r.source);
            std::vector<probe::CubeLevels> filtered = filter.run(sources);
            for (std::size_t b = 0; b < count; ++b) results[b].*levels = std::move(filtered[b]);
        }

        // The batch's dispatches filter every probe of it: each probe ran them all.
        const std::vector<probe::gpu::Dispatch>& all = filter.dispatches();
        const std::vector<probe::gpu::PassTime> levelTimes = filter.levelTimings(); // set.levels' order; a probe alone
        for (std::size_t b = 0; b < count; ++b) {
            const probe::SceneProbe& q = *results[b].probe;
            std::vector<probe::gpu::Dispatch> pyramid, others;
            for (const probe::gpu::Dispatch& d : all) (d.pass == "pyramid" ? pyramid : others).push_back(d);
            if (!pyramid.empty())
                passes[b].push_back(
                    pass(set.sheen ? probe::sheenPyramidPass(q.name, set.pyramidDepth) : probe::pyramidPass(q.name, set.pyramidDepth),
                         "gpu", describeDispatches(pyramid)));
            // Named by what ran: the method's pass, or FIS at a level the table hands to it; a dispatch
            // that writes several levels (a batch's) is each one's.
            for (const probe::gpu::Dispatch& d : others) {
                const probe::MethodKind ran = probe::parseMethodKind(d.pass);
                for (int m = d.level; m < d.level + d.levels; ++m)
                    passes[b].push_back(pass(set.sheen ? probe::sheenLevelPass(q.name, m, ran) : probe::levelPass(q.name, m, ran), "gpu",
                                             describeDispatches({d})));
            }

            json written = json::array();
            for (std::size_t k = 0; k < set.levels.size(); ++k) {
                const int m = set.levels[k];
                json level = {{"level", m},
                              {"face_size", q.faceSize >> m},
                              {"roughness", probe::levelRoughness(q.mapping, m, q.levelCount)},
                              {"alpha", probe::lobeAlpha(set.method.lobe, probe::levelAlpha(q.mapping, m, q.levelCount))},
                              {"method", std::string(probe::methodKindName(set.methods[k]))},
                              {"read_by", set.readers[k]}};
                if (count == 1 && k < levelTimes.size()) level["gpu_ms"] = levelTimes[k].medianMs;
                if (scene_.outputs.exr) {
                    const std::string file = q.name + "/" + (set.sheen ? "sheen_" : "") + probe::levelFileName(m);
                    probe::writeExr(output_.file(file), probe::cubeToStrip((results[b].*levels)[m]));
                    level["file"] = file;
                }
                written.push_back(std::move(level));
            }
            json& entry = entries[b];
            entry["levels"] = std::move(written);
            entry["pyramid_depth"] = set.pyramidDepth;
            if (set.method.kind == probe::MethodKind::fis) entry["fis_samples"] = set.method.fis.samples;
            entry["sampling"] = std::string(probe::gpu::samplingName(filter.sampling()));
            entry["gpu_ms"] = medianTimes(filter.timings());
            entry["barriers"] = filter.barriers();
            if (count > 1) {
                json names = json::array();
                for (const ProbeResult& r : results) names.push_back(r.probe->name);
                // gpu_ms is then the whole batch's: one recording.
                entry["batch"] = {{"probes", names}, {"dispatches", all.size()}, {"barriers", filter.barriers()}};
            }
        }
    }

    // The irradiance the plan asks for, into the probe's folder (irradiance_output.h).
    void writeProbeIrradiance(const probe::SceneProbe& p, const probe::ProbePlan& plan, ProbeResult& result, json& entry, json& ran) {
        const IrradianceOutput which = plan.shIrradiance && plan.irradianceCube ? IrradianceOutput::both
                                       : plan.shIrradiance                      ? IrradianceOutput::sh
                                                                                : IrradianceOutput::cube;
        const IrradianceResult irradiance = writeIrradiance(output_, p.name + "/", which, device_, result.source);
        result.irradiance = irradiance.sh;
        if (plan.shIrradiance) ran.push_back(pass(probe::irradiancePass(p.name), "gpu", describeDispatches(irradiance.shDispatches)));
        if (plan.irradianceCube) ran.push_back(pass(probe::irradianceCubePass(p.name), "cpu"));
        entry["irradiance"] = irradiance.report;
    }

    const RunOptions& options_;
    const probe::Scene& scene_;
    probe::StagedOutput& output_;
    const probe::gpu::Device& device_;
    std::vector<ProbeResult> results_;
    std::optional<probe::Image> dfg_, sheenTable_;
    json probes_ = json::array();          // in the order the batches ran them
    std::vector<std::size_t> probeOrder_;  // each entry's index in the scene
    std::map<std::size_t, json> probeRan_; // per probe (by its index in the scene), the passes it ran
    json ran_ = json::array();             // the scene's own passes (the lookup tables)
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
    for (const std::vector<std::size_t>& batch : batches(scene, plan)) run.runBatch(plan, batch);
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
