#include "probe/plan.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "probe/pyramid.h"

namespace probe {

std::vector<int> levelsReadForRoughness(const RoughnessMapping& mapping, double roughness, int levelCount) {
    const double level = roughnessToLevel(mapping, roughness, levelCount);
    const int lower = static_cast<int>(std::floor(level)), upper = static_cast<int>(std::ceil(level));
    return lower == upper ? std::vector<int>{lower} : std::vector<int>{lower, upper};
}

namespace {

// Far above the float rounding of a tap level (~1e-6), far below any tap spacing that matters.
constexpr double kLevelMargin = 1e-3;

} // namespace

int deepestPyramidLevelRead(const TapGenerator& generator, int faceSize, const std::vector<int>& levels) {
    const int maxLevel = pyramidLevelCount(faceSize) - 1;
    int deepest = 0;
    std::vector<Tap> taps;
    for (int m : levels) {
        const int size = faceSize >> m;
        for (int f = 0; f < kFaceCount; ++f)
            for (int j = 0; j < size; ++j)
                for (int i = 0; i < size; ++i) {
                    if (!generator(m, {f, i, j}, taps)) continue;
                    for (const Tap& tap : taps) {
                        if (tap.weight == 0.0) continue;
                        // A level clamped to an end of the pyramid is exact in float too; elsewhere
                        // the GPU's float level may land just above a whole level that the double
                        // lands on (or just below), and then reads the next level with a tiny weight.
                        const double level = std::clamp(tap.level, 0.0, double(maxLevel));
                        const int reads = level == 0.0 || level == maxLevel ? static_cast<int>(level)
                                                                            : static_cast<int>(std::floor(level + kLevelMargin)) + 1;
                        deepest = std::max(deepest, std::min(reads, maxLevel));
                    }
                }
    }
    return deepest;
}

FilterMethod sheenMethod(const SceneProbe& probe, bool charlieTable) {
    FilterMethod method = probe.method;
    method.lobe = Lobe::charlie;
    if (method.kind == MethodKind::table && !charlieTable) method.kind = MethodKind::fis;
    method.table = nullptr;
    return method;
}

std::vector<MethodKind> levelMethods(MethodKind kind, const TapTable* table, int levelCount) {
    std::vector<MethodKind> methods(static_cast<std::size_t>(levelCount), kind);
    if (kind == MethodKind::table && table)
        for (int m = 0; m < levelCount; ++m)
            if (table->levels[m].fisSamples > 0) methods[m] = MethodKind::fis;
    return methods;
}

Plan makePlan(const Scene& scene, const MethodTapsFor& methodTapsFor, const CharlieTableFor& charlieTableFor) {
    Plan plan;
    for (const SceneProbe& probe : scene.probes) {
        ProbePlan p;
        p.probe = probe.name;
        p.method = probe.method.kind;
        std::map<int, std::vector<std::string>> readers, sheenReaders;
        for (const SceneMaterial& material : scene.materials) {
            if (material.probe != probe.name) continue;
            if (material.hasSpecular())
                for (int level : levelsReadForRoughness(probe.mapping, material.roughness, probe.levelCount))
                    readers[level].push_back(material.name);
            if (material.hasDiffuse()) p.diffuseMaterials.push_back(material.name);
            if (material.hasSheen())
                for (int level : levelsReadForRoughness(probe.mapping, material.sheenRoughness, probe.levelCount))
                    sheenReaders[level].push_back(material.name);
        }
        const MethodTaps ggx = readers.empty() ? MethodTaps{} : methodTapsFor(probe);
        for (auto& [level, names] : readers) {
            p.computedLevels.push_back(level);
            p.levelReaders.push_back(names);
            p.levelMethods.push_back(ggx.levelMethods[level]);
        }
        // Every Charlie level is filtered (none is a copy); FIS reads the pyramid, the reference the source.
        const FilterMethod sheen = sheenMethod(probe, !sheenReaders.empty() && charlieTableFor(probe));
        p.sheenMethod = sheen.kind;
        SceneProbe charlie = probe;
        charlie.method = sheen;
        const MethodTaps charlieTaps = sheenReaders.empty() ? MethodTaps{} : methodTapsFor(charlie);
        for (auto& [level, names] : sheenReaders) {
            p.sheenLevels.push_back(level);
            p.sheenReaders.push_back(names);
            p.sheenLevelMethods.push_back(charlieTaps.levelMethods[level]);
        }
        if (!p.sheenLevels.empty() && p.sheenMethod != MethodKind::reference)
            p.sheenPyramidLevels = deepestPyramidLevelRead(charlieTaps.generator, probe.faceSize, p.sheenLevels);
        p.shIrradiance = !p.diffuseMaterials.empty() && (scene.outputs.shIrradiance || scene.outputs.spheres);
        p.irradianceCube = !p.diffuseMaterials.empty() && scene.outputs.irradianceCube;
        p.readsPyramid = std::any_of(p.computedLevels.begin(), p.computedLevels.end(),
                                     [&](int m) { return levelAlpha(probe.mapping, m, probe.levelCount) > 0.0; });
        // The reference reads pyramid level 0, the source, texel by texel.
        if (p.readsPyramid && probe.method.kind != MethodKind::reference)
            p.pyramidLevels = deepestPyramidLevelRead(ggx.generator, probe.faceSize, p.computedLevels);
        plan.probes.push_back(std::move(p));
    }
    for (const SceneMaterial& material : scene.materials) {
        if (material.hasSpecular()) plan.specularMaterials.push_back(material.name);
        if (material.hasSheen()) plan.sheenMaterials.push_back(material.name);
    }
    plan.dfgTable = !plan.specularMaterials.empty();
    plan.sheenTable = !plan.sheenMaterials.empty();
    return plan;
}

std::string loadPass(const std::string& probe) { return fmt::format("{}: load", probe); }
std::string pyramidPass(const std::string& probe, int depth) { return fmt::format("{}: pyramid 0..{}", probe, depth); }
std::string levelPass(const std::string& probe, int level, MethodKind method) {
    return fmt::format("{}: level {} ({})", probe, level, methodKindName(method));
}
std::string irradiancePass(const std::string& probe) { return fmt::format("{}: sh-irradiance", probe); }
std::string irradianceCubePass(const std::string& probe) { return fmt::format("{}: irradiance-cube", probe); }
std::string sheenPyramidPass(const std::string& probe, int depth) { return fmt::format("{}: sheen pyramid 0..{}", probe, depth); }
std::string sheenLevelPass(const std::string& probe, int level, MethodKind method) {
    return fmt::format("{}: sheen level {} ({})", probe, level, methodKindName(method));
}

namespace {

struct Step {
    std::string pass;
    std::string reason;
};

// Why a level of a table probe is FIS's: the table hands it over.
std::string handOffReason(MethodKind probeMethod, MethodKind levelMethod) {
    return probeMethod != levelMethod ? "; the table hands it to FIS, which filters it better at no more time" : "";
}

std::vector<Step> steps(const Plan& plan) {
    std::vector<Step> out;
    for (const ProbePlan& p : plan.probes) {
        if (!p.used()) continue;
        out.push_back({loadPass(p.probe), "the probe is read by some material"});
        if (p.readsPyramid)
            out.push_back({pyramidPass(p.probe, p.pyramidLevels),
                           p.method == MethodKind::reference
                               ? fmt::format("the reference of levels {} reads the source (pyramid level 0) texel by texel",
                                             fmt::join(p.computedLevels, ", "))
                               : fmt::format("the taps of levels {} read down to pyramid level {} (level 0: the source)",
                                             fmt::join(p.computedLevels, ", "), p.pyramidLevels)});
        for (std::size_t k = 0; k < p.computedLevels.size(); ++k)
            out.push_back({levelPass(p.probe, p.computedLevels[k], p.levelMethods[k]),
                           fmt::format("read by {}{}", fmt::join(p.levelReaders[k], ", "), handOffReason(p.method, p.levelMethods[k]))});
        if (p.shIrradiance) out.push_back({irradiancePass(p.probe), fmt::format("diffuse: {}", fmt::join(p.diffuseMaterials, ", "))});
        if (p.irradianceCube)
            out.push_back({irradianceCubePass(p.probe),
                           fmt::format("diffuse: {}; the outputs ask for the cube", fmt::join(p.diffuseMaterials, ", "))});
        if (!p.sheenLevels.empty() && p.sheenMethod != MethodKind::reference)
            out.push_back({sheenPyramidPass(p.probe, p.sheenPyramidLevels),
                           fmt::format("the Charlie {} taps of sheen levels {} read down to pyramid level {}",
                                       p.sheenMethod == MethodKind::table ? "table's" : "FIS", fmt::join(p.sheenLevels, ", "),
                                       p.sheenPyramidLevels)});
        for (std::size_t k = 0; k < p.sheenLevels.size(); ++k)
            out.push_back({sheenLevelPass(p.probe, p.sheenLevels[k], p.sheenLevelMethods[k]),
                           fmt::format("sheen read by {}{}", fmt::join(p.sheenReaders[k], ", "),
                                       handOffReason(p.sheenMethod, p.sheenLevelMethods[k]))});
    }
    if (plan.dfgTable) out.push_back({kDfgPass, fmt::format("specular: {}", fmt::join(plan.specularMaterials, ", "))});
    if (plan.sheenTable) out.push_back({kSheenTablePass, fmt::format("sheen: {}", fmt::join(plan.sheenMaterials, ", "))});
    return out;
}

} // namespace

std::vector<std::string> Plan::passes() const {
    std::vector<std::string> out;
    for (const Step& s : steps(*this)) out.push_back(s.pass);
    return out;
}

std::vector<std::string> Plan::explain() const {
    std::vector<std::string> out;
    for (const Step& s : steps(*this)) out.push_back(fmt::format("{:<32} because {}", s.pass, s.reason));
    return out;
}

} // namespace probe
