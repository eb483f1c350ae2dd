// What a scene calls for, and nothing else: per probe the output levels its specular materials
// read, the pyramid only as deep as those levels' taps reach, irradiance only for diffuse
// materials, the Charlie levels only for materials with sheen; the split-sum DFG table only if some
// material is specular, the sheen table only if some material has sheen.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "probe/scene.h"
#include "probe/tap_sum.h"

namespace probe {

// The output levels that a trilinear lookup at `roughness` reads under the mapping: floor and
// ceil of the fractional level (one level when it is whole).
std::vector<int> levelsReadForRoughness(const RoughnessMapping& mapping, double roughness, int levelCount);

// The deepest pyramid level that the taps of the given output levels read (trilinear reads the
// level above a fractional level too), clamped to the pyramid; 0 when no level has taps. A tap
// level within 1e-3 below or at a whole level k counts as reading k + 1, so that the GPU's float
// tap levels read no deeper either.
int deepestPyramidLevelRead(const TapGenerator& generator, int faceSize, const std::vector<int>& levels);

struct ProbePlan {
    std::string probe;
    MethodKind method = MethodKind::table;
    std::vector<int> computedLevels;                    // output levels to compute, ascending
    std::vector<std::vector<std::string>> levelReaders; // per entry of `computedLevels`: the materials that read it
    std::vector<MethodKind> levelMethods;               // per entry of `computedLevels`: how it is filtered (levelMethods())
    bool readsPyramid = false;                          // some level is filtered (not a copy of the source)
    int pyramidLevels = 0;                              // pyramid levels to build below the source (the reference: 0)
    bool shIrradiance = false;                          // some material is diffuse, and the outputs or the spheres want SH
    bool irradianceCube = false;                        // some material is diffuse, and the outputs want the cube
    std::vector<std::string> diffuseMaterials;
    // The Charlie levels its materials with sheen read (sheenMethod), as `computedLevels` and
    // `pyramidLevels` are for GGX; the sheen pyramid is its own (a FIS pyramid as deep as they read).
    MethodKind sheenMethod = MethodKind::fis;
    std::vector<int> sheenLevels;
    std::vector<std::vector<std::string>> sheenReaders;
    std::vector<MethodKind> sheenLevelMethods;
    int sheenPyramidLevels = 0;

    // Whether anything of the probe is computed (it is loaded at all).
    bool used() const { return !computedLevels.empty() || shIrradiance || irradianceCube || !sheenLevels.empty(); }
};

struct Plan {
    std::vector<ProbePlan> probes;
    bool dfgTable = false;
    std::vector<std::string> specularMaterials;
    bool sheenTable = false;
    std::vector<std::string> sheenMaterials;

    // The passes in execution order, one line each: "<probe>: <pass>", or "dfg-table". This is
    // the list that a run's report.json records as the dispatches it ran.
    std::vector<std::string> passes() const;
    // passes() with the reason for each, for people.
    std::vector<std::string> explain() const;
};

// The name of each pass, as Plan::passes() lists it and a run records what it ran.
std::string loadPass(const std::string& probe);
std::string pyramidPass(const std::string& probe, int depth); // pyramid levels 0 (the border) to depth
std::string levelPass(const std::string& probe, int level, MethodKind method);
std::string irradiancePass(const std::string& probe);
std::string irradianceCubePass(const std::string& probe);
std::string sheenPyramidPass(const std::string& probe, int depth);
std::string sheenLevelPass(const std::string& probe, int level, MethodKind method);
inline constexpr const char* kDfgPass = "dfg-table";
inline constexpr const char* kSheenTablePass = "sheen-table";

// How a probe's Charlie levels are filtered: the probe's method with the Charlie lobe; where it is a
// table, a Charlie table where one fits the probe (`charlieTable`), else FIS with the probe's samples.
FilterMethod sheenMethod(const SceneProbe& probe, bool charlieTable);

// How a method filters each of `levelCount` output levels: its kind, or FIS at the levels a table
// hands to it (TableLevel::fisSamples).
std::vector<MethodKind> levelMethods(MethodKind kind, const TapTable* table, int levelCount);

// A probe's method with its lobe: the tap generator (empty for the reference, which reads no
// pyramid) and levelMethods().
struct MethodTaps {
    TapGenerator generator;
    std::vector<MethodKind> levelMethods;
};
using MethodTapsFor = std::function<MethodTaps(const SceneProbe&)>;
// Whether a Charlie table fits a probe.
using CharlieTableFor = std::function<bool(const SceneProbe&)>;

// What a scene needs computed: per probe the levels its materials read and the pyramid those levels
// read, the irradiance where a material is diffuse, the Charlie levels where one has sheen; the DFG
// table where one is specular, the sheen table where one has sheen.
Plan makePlan(const Scene& scene, const MethodTapsFor& methodTapsFor, const CharlieTableFor& charlieTableFor);

} // namespace probe
