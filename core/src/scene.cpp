#include "probe/scene.h"

#include <algorithm>
#include <limits>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "probe/error.h"
#include "probe/input_file.h"
#include "probe/json_input.h"
#include "probe/limits.h"

namespace probe {

namespace {

using nlohmann::json;

// Reads one JSON object field by field, so that every error names the field and unknown fields
// are refused.
class FieldReader {
public:
    FieldReader(const std::filesystem::path& scene, std::string where, const json& object)
        : scene_(scene), where_(std::move(where)), object_(object) {
        if (!object_.is_object()) fail(where_, "must be an object");
    }

    [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
        throw ProbeError(fmt::format("{}: {}: {}", scene_.string(), field, problem));
    }
    std::string field(const std::string& key) const { return where_.empty() ? key : fmt::format("{}.{}", where_, key); }

    template <typename T>
    std::optional<T> optional(const std::string& key) {
        seen_.insert(key);
        const auto it = object_.find(key);
        if (it == object_.end()) return std::nullopt;
        if constexpr (std::is_same_v<T, int>) {
            const std::optional<int> value = jsonInt(*it);
            if (!value) fail(field(key), fmt::format("{} is not an integer within int's range", describeJson(*it)));
            return value;
        } else if constexpr (std::is_same_v<T, double>) {
            if (!it->is_number()) fail(field(key), fmt::format("wrong type ({}, a number expected)", describeJson(*it)));
            return it->template get<double>();
        } else {
            try {
                return it->template get<T>();
            } catch (const json::exception&) {
                fail(field(key), fmt::format("wrong type ({})", describeJson(*it)));
            }
        }
    }
    template <typename T>
    T required(const std::string& key) {
        auto value = optional<T>(key);
        if (!value) fail(field(key), "missing");
        return *value;
    }
    // A number in [0, 1]; required when there is no fallback.
    double unitInterval(const std::string& key, std::optional<double> fallback) {
        const std::optional<double> read = optional<double>(key);
        if (!read && !fallback) fail(field(key), "missing");
        const double value = read ? *read : *fallback;
        if (!(value >= 0.0 && value <= 1.0)) fail(field(key), fmt::format("{} is outside [0, 1]", value));
        return value;
    }
    // Three numbers in [0, 1], if given.
    std::optional<glm::dvec3> color(const std::string& key) {
        const std::optional<std::vector<double>> c = optional<std::vector<double>>(key);
        if (!c) return std::nullopt;
        if (c->size() != 3) fail(field(key), "must hold 3 numbers");
        for (double v : *c)
            if (!(v >= 0.0 && v <= 1.0)) fail(field(key), fmt::format("{} is outside [0, 1]", v));
        return glm::dvec3((*c)[0], (*c)[1], (*c)[2]);
    }
    const json& child(const std::string& key) {
        seen_.insert(key);
        static const json empty = json::object();
        const auto it = object_.find(key);
        return it == object_.end() ? empty : *it;
    }
    // Call last: every key must have been read.
    void refuseUnknown() const {
        for (const auto& [key, value] : object_.items())
            if (!seen_.count(key)) fail(field(key.substr(0, 64)), "unknown field");
    }

private:
    const std::filesystem::path& scene_;
    std::string where_;
    const json& object_;
    std::set<std::string> seen_;
};

template <typename Parse>
auto parseNamed(FieldReader& reader, const std::string& key, const std::string& value, Parse parse) {
    try {
        return parse(value);
    } catch (const ProbeError& e) {
        reader.fail(reader.field(key), e.what());
    }
}

SceneProbe readProbe(const std::filesystem::path& scene, const std::string& where, const json& object) {
    FieldReader r(scene, where, object);
    SceneProbe p;
    p.name = r.required<std::string>("name");
    // A probe's outputs go to a folder of its name, beside the run's own files.
    const bool control =
        std::any_of(p.name.begin(), p.name.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
    if (p.name.empty() || p.name == "." || p.name == ".." || p.name.find_first_of("/\\") != std::string::npos || control)
        r.fail(r.field("name"), fmt::format("'{}' cannot name a folder", p.name));
    if (p.name == "report.json" || p.name == "dfg.exr" || p.name == "sheen.exr")
        r.fail(r.field("name"), fmt::format("'{}' is the name of one of the run's own files", p.name));
    p.image = scene.parent_path() / r.required<std::string>("image");
    try {
        checkInputFile(p.image, std::numeric_limits<std::uintmax_t>::max());
    } catch (const ProbeError& e) {
        r.fail(r.field("image"), e.what());
    }
    p.faceSize = r.optional<int>("face_size").value_or(128);
    if (log2Exact(p.faceSize) < 0 || p.faceSize > kMaxFaceSize)
        r.fail(r.field("face_size"), fmt::format("{} is not a power of two from 1 to {}", p.faceSize, kMaxFaceSize));
    // The roughness per level: a named mapping, or a list of its own (one value per level).
    const std::optional<std::string> mapping = r.optional<std::string>("mapping");
    const std::optional<std::vector<double>> roughness = r.optional<std::vector<double>>("roughness");
    if (mapping && roughness) r.fail(r.field("roughness"), "is given with \"mapping\": give one of them");
    if (roughness) {
        try {
            p.mapping = RoughnessMapping::custom(*roughness);
        } catch (const ProbeError& e) {
            r.fail(r.field("roughness"), e.what());
        }
    } else {
        p.mapping = parseNamed(r, "mapping", mapping.value_or("gltf"), parseRoughnessMapping);
    }
    const std::optional<int> levels = r.optional<int>("levels");
    try {
        p.levelCount = chooseLevelCount(p.faceSize, levels, p.mapping);
    } catch (const ProbeError& e) {
        r.fail(r.field(levels ? "levels" : "roughness"), e.what());
    }
    p.method.kind = parseNamed(r, "method", r.optional<std::string>("method").value_or("table"), parseMethodKind);
    p.method.fis.samples = r.optional<int>("samples").value_or(32);
    if (p.method.fis.samples < 1 || p.method.fis.samples > kMaxSamples)
        r.fail(r.field("samples"), fmt::format("{} is not a sample count from 1 to {}", p.method.fis.samples, kMaxSamples));
    if (auto table = r.optional<std::string>("table")) p.table = scene.parent_path() / *table;
    r.refuseUnknown();
    return p;
}

SceneMaterial readMaterial(const std::filesystem::path& scene, const std::string& where, const json& object) {
    FieldReader r(scene, where, object);
    SceneMaterial m;
    m.name = r.required<std::string>("name");
    m.probe = r.optional<std::string>("probe").value_or("");
    m.roughness = r.unitInterval("roughness", std::nullopt);
    m.metallic = r.unitInterval("metallic", 0.0);
    m.specular = r.unitInterval("specular", 1.0);
    if (auto color = r.color("base_color")) m.baseColor = *color;
    if (auto color = r.color("sheen_color")) m.sheenColor = *color;
    m.sheenRoughness = r.unitInterval("sheen_roughness", 0.0);
    r.refuseUnknown();
    return m;
}

SceneOutputs readOutputs(const std::filesystem::path& scene, const json& object) {
    FieldReader r(scene, "outputs", object);
    SceneOutputs o;
    o.exr = r.optional<bool>("exr").value_or(true);
    o.spheres = r.optional<bool>("spheres").value_or(false);
    const json& ktx2 = r.child("ktx2");
    std::optional<Ktx2PixelFormat> format;
    if (ktx2.is_boolean()) format = ktx2.get<bool>() ? std::optional(Ktx2PixelFormat::rgba16f) : std::nullopt;
    else if (ktx2.is_string() && parseKtx2PixelFormat(ktx2.get<std::string>())) format = parseKtx2PixelFormat(ktx2.get<std::string>());
    else if (!(ktx2.is_object() && ktx2.empty()))
        r.fail("outputs.ktx2", fmt::format("{} is not rgba16f, rgba32f, rgb9e5, bc6h or a boolean", describeJson(ktx2)));
    const bool zstd = r.optional<bool>("ktx2_zstd").value_or(false);
    if (zstd && !format) r.fail("outputs.ktx2_zstd", "true, but outputs.ktx2 writes no probe.ktx2");
    if (format) o.ktx2 = Ktx2Settings{*format, zstd ? Ktx2Supercompression::zstd : Ktx2Supercompression::none};
    const std::string irradiance = r.optional<std::string>("irradiance").value_or("sh");
    if (irradiance != "sh" && irradiance != "cube" && irradiance != "both")
        r.fail("outputs.irradiance", fmt::format("'{}' is not sh, cube or both", irradiance));
    o.shIrradiance = irradiance != "cube";
    o.irradianceCube = irradiance != "sh";
    r.refuseUnknown();
    return o;
}

} // namespace

Scene readScene(const std::filesystem::path& path) {
    const json root = parseJsonFile(readTextFile(path), path, "scene file");
    Scene scene;
    scene.path = path;
    FieldReader r(path, "", root);
    const int version = r.optional<int>("version").value_or(kSceneFormatVersion);
    if (version != kSceneFormatVersion)
        r.fail("version", fmt::format("{}: this build reads scene format version {}", version, kSceneFormatVersion));
    const json& probes = r.child("probes");
    const json& materials = r.child("materials");
    if (!probes.is_array() || probes.empty()) r.fail("probes", "must be a non-empty array");
    if (probes.size() > kMaxSceneProbes) r.fail("probes", fmt::format("{} probes, over the limit of {}", probes.size(), kMaxSceneProbes));
    if (!materials.is_array()) r.fail("materials", "must be an array");
    if (materials.size() > kMaxSceneMaterials)
        r.fail("materials", fmt::format("{} materials, over the limit of {}", materials.size(), kMaxSceneMaterials));
    scene.outputs = readOutputs(path, r.child("outputs"));
    r.refuseUnknown();

    std::set<std::string> probeNames, materialNames;
    for (std::size_t k = 0; k < probes.size(); ++k) {
        const std::string where = fmt::format("probes[{}]", k);
        scene.probes.push_back(readProbe(path, where, probes[k]));
        if (!probeNames.insert(scene.probes.back().name).second)
            r.fail(where + ".name", fmt::format("duplicate probe name '{}'", scene.probes.back().name));
    }
    for (std::size_t k = 0; k < materials.size(); ++k) {
        const std::string where = fmt::format("materials[{}]", k);
        SceneMaterial m = readMaterial(path, where, materials[k]);
        if (!materialNames.insert(m.name).second) r.fail(where + ".name", fmt::format("duplicate material name '{}'", m.name));
        if (m.probe.empty()) {
            if (scene.probes.size() != 1) r.fail(where + ".probe", "missing (the scene has several probes)");
            m.probe = scene.probes.front().name;
        } else if (!probeNames.count(m.probe)) {
            r.fail(where + ".probe", fmt::format("no probe named '{}'", m.probe));
        }
        scene.materials.push_back(std::move(m));
    }
    return scene;
}

} // namespace probe
