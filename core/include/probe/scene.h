// Scene files: the probes a scene uses and the materials they light. A scene decides what is
// computed: only the levels and effects its materials need (plan.h).
//
// {
//   "version": 1,
//   "probes": [{"name": "sunset", "image": "sunset.exr", "face_size": 128, "levels": 7,
//               "mapping": "gltf", "method": "table", "samples": 32, "table": "t.json"}],
//   "materials": [{"name": "chrome", "probe": "sunset", "roughness": 0.05, "metallic": 1,
//                  "base_color": [0.95, 0.93, 0.88], "specular": 1},
//                 {"name": "velvet", "roughness": 0.8, "sheen_color": [0.6, 0.1, 0.2], "sheen_roughness": 0.4}],
//   "outputs": {"exr": true, "ktx2": "rgba16f", "ktx2_zstd": false, "spheres": true, "irradiance": "sh"}
// }
// A probe's "roughness" (a list, one perceptual roughness per level, increasing) replaces "mapping".
// A probe's name names its output folder (no slashes). Only "name" and "image" of a probe and
// "name" and "roughness" of a material are required; "probe" may be left out when there is one
// probe. Paths are relative to the scene file. "version" (the format's, 1) may be left out; another
// version is refused.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "probe/filter_method.h"
#include "probe/ktx2.h"
#include "probe/roughness.h"

namespace probe {

inline constexpr int kSceneFormatVersion = 1;

struct SceneProbe {
    std::string name;
    std::filesystem::path image; // resolved against the scene's folder
    int faceSize = 128;
    int levelCount = 0; // after parsing: the roughness list's length or the default for the face size when not given
    RoughnessMapping mapping = RoughnessMapping::gltf;
    FilterMethod method;                        // its table is left null: `table` or the compiled-in one
    std::optional<std::filesystem::path> table; // table method: a table file instead of the compiled-in one
};

struct SceneMaterial {
    std::string name;
    std::string probe;
    double roughness = 0.5; // perceptual, [0, 1]
    double metallic = 0.0;  // [0, 1]
    glm::dvec3 baseColor{0.8};
    double specular = 1.0;      // dielectric specular strength (F0 = 0.04 specular), [0, 1]
    glm::dvec3 sheenColor{0.0}; // KHR_materials_sheen: black is no sheen
    double sheenRoughness = 0.0;

    // Lit by the prefiltered GGX levels (and the DFG table).
    bool hasSpecular() const { return metallic > 0.0 || specular > 0.0; }
    // Lit by the prefiltered Charlie levels (and the sheen table).
    bool hasSheen() const { return sheenColor.r > 0.0 || sheenColor.g > 0.0 || sheenColor.b > 0.0; }
    // Lit by irradiance.
    bool hasDiffuse() const { return metallic < 1.0 && (baseColor.r > 0.0 || baseColor.g > 0.0 || baseColor.b > 0.0); }
};

struct SceneOutputs {
    bool exr = true;
    std::optional<Ktx2Settings> ktx2; // none: no probe.ktx2
    bool spheres = false;
    // The Lambertian irradiance of a probe that a diffuse material reads: "sh" (the default), "cube"
    // or "both" (probe/irradiance.h). The spheres shade diffuse with the SH, so they ask for it too.
    bool shIrradiance = true;
    bool irradianceCube = false;
};

struct Scene {
    std::filesystem::path path;
    std::vector<SceneProbe> probes;
    std::vector<SceneMaterial> materials;
    SceneOutputs outputs;
};

// Reads and validates a scene. Throws ProbeError "<scene file>: <field>: <problem>" for a missing
// image, an unknown field, a value out of range, a duplicate or dangling name.
Scene readScene(const std::filesystem::path& path);

} // namespace probe
