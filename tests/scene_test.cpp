// Scenes and plans: exact passes for mirror-only, diffuse-only, mixed and empty scenes; bad scene
// files name the file and the field.
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "probe/cpu_filter.h"
#include "probe/error.h"
#include "probe/fis.h"
#include "probe/plan.h"
#include "probe/probe_io.h"
#include "probe/pyramid.h"
#include "probe/synthetic.h"

using namespace probe;
namespace fs = std::filesystem;

namespace {

class SceneTest : public ::testing::Test {
protected:
    fs::path dir = fs::temp_directory_path() /
                   fmt::format("scene_test_{}_{}", ::getpid(), ::testing::UnitTest::GetInstance()->current_test_info()->name());
    void SetUp() override {
        fs::create_directories(dir);
        writeExr(dir / "sky.exr", cubeToStrip(skyProbe(16)));
    }
    void TearDown() override { fs::remove_all(dir); }

    fs::path write(const std::string& json) {
        const fs::path path = dir / "scene.json";
        std::ofstream(path) << json;
        return path;
    }
    static std::string scene(const std::string& materials) {
        return fmt::format(R"({{"probes": [{{"name": "sky", "image": "sky.exr", "face_size": 16, "method": "fis"}}],
                               "materials": [{}]}})",
                           materials);
    }
    Plan plan(const std::string& json) {
        const Scene s = readScene(write(json));
        return makePlan(
            s,
            [](const SceneProbe& p) {
                return MethodTaps{methodTapGenerator(p.method, p.faceSize, p.levelCount, p.mapping),
                                  levelMethods(p.method.kind, p.method.table, p.levelCount)};
            },
            [](const SceneProbe&) { return false; });
    }
    void expectRefused(const std::string& json, const std::string& field) {
        try {
            readScene(write(json));
            FAIL() << "accepted: " << json;
        } catch (const ProbeError& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find((dir / "scene.json").string()), std::string::npos) << message;
            EXPECT_NE(message.find(field), std::string::npos) << message;
        }
    }
};

} // namespace

TEST(Plan, LevelsReadForRoughness) {
    // glTF, 7 levels: lod = 6 r.
    EXPECT_EQ(levelsReadForRoughness(RoughnessMapping::gltf, 0.0, 7), (std::vector<int>{0}));
    EXPECT_EQ(levelsReadForRoughness(RoughnessMapping::gltf, 0.5, 7), (std::vector<int>{3}));
    EXPECT_EQ(levelsReadForRoughness(RoughnessMapping::gltf, 0.3, 7), (std::vector<int>{1, 2}));
    EXPECT_EQ(levelsReadForRoughness(RoughnessMapping::gltf, 1.0, 7), (std::vector<int>{6}));
    // Every mapping inverts its own roughness per level.
    for (const std::string& name : roughnessMappingNames())
        for (int m = 0; m < 7; ++m) {
            const RoughnessMapping mapping = parseRoughnessMapping(name);
            EXPECT_NEAR(roughnessToLevel(mapping, levelRoughness(mapping, m, 7), 7), m, 1e-9) << name;
        }
}

TEST_F(SceneTest, MirrorOnly) {
    const Plan p = plan(scene(R"({"name": "chrome", "roughness": 0, "metallic": 1, "base_color": [1, 1, 1]})"));
    EXPECT_EQ(p.passes(), (std::vector<std::string>{"sky: load", "sky: level 0 (fis)", "dfg-table"}));
}

TEST_F(SceneTest, DiffuseOnly) {
    const Plan p = plan(scene(R"({"name": "chalk", "roughness": 1, "metallic": 0, "specular": 0})"));
    EXPECT_EQ(p.passes(), (std::vector<std::string>{"sky: load", "sky: sh-irradiance"}));
}

// The Lambertian cube only when the outputs ask for it and a material is diffuse; SH as asked, and
// for the spheres, which shade diffuse with it.
TEST_F(SceneTest, IrradianceCubeOnlyWhenAsked) {
    const auto withOutputs = [](const std::string& materials, const std::string& outputs) {
        return fmt::format(R"({{"probes": [{{"name": "sky", "image": "sky.exr", "face_size": 16, "method": "fis"}}],
                               "materials": [{}], "outputs": {{{}}}}})",
                           materials, outputs);
    };
    const std::string chalk = R"({"name": "chalk", "roughness": 1, "specular": 0})";
    const std::string chrome = R"({"name": "chrome", "roughness": 0, "metallic": 1})";
    EXPECT_EQ(plan(withOutputs(chalk, R"("irradiance": "both")")).passes(),
              (std::vector<std::string>{"sky: load", "sky: sh-irradiance", "sky: irradiance-cube"}));
    EXPECT_EQ(plan(withOutputs(chalk, R"("irradiance": "cube")")).passes(),
              (std::vector<std::string>{"sky: load", "sky: irradiance-cube"}));
    EXPECT_EQ(plan(withOutputs(chalk, R"("irradiance": "cube", "spheres": true)")).passes(),
              (std::vector<std::string>{"sky: load", "sky: sh-irradiance", "sky: irradiance-cube"}));
    EXPECT_EQ(plan(withOutputs(chrome, R"("irradiance": "both")")).passes(),
              (std::vector<std::string>{"sky: load", "sky: level 0 (fis)", "dfg-table"}));
    expectRefused(withOutputs(chalk, R"("irradiance": "lambert")"), "outputs.irradiance");
}

// outputs.ktx2 names a format (true is RGBA16F) and ktx2_zstd its supercompression; another value,
// or Zstandard without a file, is refused naming the field.
TEST_F(SceneTest, Ktx2OutputNamesItsFormat) {
    const auto withKtx2 = [](const std::string& ktx2) {
        return fmt::format(R"({{"probes": [{{"name": "sky", "image": "sky.exr", "face_size": 16}}],
                               "materials": [{{"name": "chrome", "roughness": 0, "metallic": 1}}], "outputs": {{"ktx2": {}}}}})",
                           ktx2);
    };
    const auto ktx2Of = [&](const std::string& ktx2) { return readScene(write(withKtx2(ktx2))).outputs.ktx2; };
    EXPECT_EQ(ktx2Of(R"("rgb9e5")")->format, Ktx2PixelFormat::rgb9e5);
    EXPECT_EQ(ktx2Of(R"("rgba32f")")->format, Ktx2PixelFormat::rgba32f);
    EXPECT_EQ(ktx2Of("true")->format, Ktx2PixelFormat::rgba16f);
    EXPECT_EQ(ktx2Of("true")->supercompression, Ktx2Supercompression::none);
    EXPECT_EQ(ktx2Of(R"("rgb9e5", "ktx2_zstd": true)")->supercompression, Ktx2Supercompression::zstd);
    EXPECT_EQ(ktx2Of(R"("bc6h")")->format, Ktx2PixelFormat::bc6h);
    EXPECT_FALSE(ktx2Of("false").has_value());
    expectRefused(withKtx2(R"("bc7")"), "outputs.ktx2");
    expectRefused(withKtx2(R"(false, "ktx2_zstd": true)"), "outputs.ktx2_zstd");
}

TEST_F(SceneTest, Mixed) {
    // 16^2 has 4 levels under glTF: lod = 3 r; r = 0.5 reads levels 1 and 2.
    const Plan p = plan(scene(R"({"name": "plastic", "roughness": 0.5}, {"name": "chrome", "roughness": 0, "metallic": 1})"));
    const int deepest = p.probes[0].pyramidLevels;
    const FisSettings fis{32, 0.0, {}, {}, FisMap::cube};
    EXPECT_EQ(deepest, deepestPyramidLevelRead(fisTapGenerator(16, 4, RoughnessMapping::gltf, fis), 16, {1, 2}));
    EXPECT_GT(deepest, 0);
    EXPECT_EQ(p.passes(), (std::vector<std::string>{"sky: load", fmt::format("sky: pyramid 0..{}", deepest), "sky: level 0 (fis)",
                                                    "sky: level 1 (fis)", "sky: level 2 (fis)", "sky: sh-irradiance", "dfg-table"}));
}

// Sheen (KHR_materials_sheen) adds the Charlie levels its sheen roughness reads, filtered by FIS over
// a pyramid as deep as their Charlie taps read, and the sheen table; a scene without sheen computes
// nothing for it.
TEST_F(SceneTest, SheenOnlyWhereAMaterialHasIt) {
    const Plan none = plan(scene(R"({"name": "plastic", "roughness": 0.5, "sheen_roughness": 0.7})"));
    EXPECT_TRUE(none.probes[0].sheenLevels.empty()) << "black sheen is no sheen";
    EXPECT_FALSE(none.sheenTable);
    for (const std::string& pass : none.passes()) EXPECT_EQ(pass.find("sheen"), std::string::npos) << pass;

    // Sheen roughness 0.5 reads levels 1 and 2; the velvet's own roughness 1 reads level 3.
    const Plan p = plan(scene(R"({"name": "velvet", "roughness": 1, "specular": 0, "base_color": [0, 0, 0],
                                  "sheen_color": [1, 0.5, 0.5], "sheen_roughness": 0.5})"));
    const ProbePlan& probe = p.probes[0];
    EXPECT_TRUE(probe.computedLevels.empty()) << "no specular term";
    EXPECT_EQ(probe.sheenLevels, (std::vector<int>{1, 2}));
    EXPECT_EQ(probe.sheenMethod, MethodKind::fis);
    FilterMethod charlie;
    charlie.kind = MethodKind::fis;
    charlie.lobe = Lobe::charlie;
    const int deepest = deepestPyramidLevelRead(methodTapGenerator(charlie, 16, 4, RoughnessMapping::gltf), 16, {1, 2});
    EXPECT_EQ(probe.sheenPyramidLevels, deepest);
    EXPECT_EQ(p.passes(), (std::vector<std::string>{"sky: load", fmt::format("sky: sheen pyramid 0..{}", deepest),
                                                    "sky: sheen level 1 (fis)", "sky: sheen level 2 (fis)", "sheen-table"}));

    // A table probe's Charlie levels are a Charlie table's where one fits it, else FIS's; the
    // reference's are the reference's.
    const Scene s = readScene(write(R"({"probes": [{"name": "sky", "image": "sky.exr", "face_size": 16, "method": "table"}],
                                        "materials": []})"));
    EXPECT_EQ(sheenMethod(s.probes[0], false).kind, MethodKind::fis);
    EXPECT_EQ(sheenMethod(s.probes[0], true).kind, MethodKind::table);
    EXPECT_EQ(sheenMethod(s.probes[0], true).lobe, Lobe::charlie);
    const Plan reference = plan(R"({"probes": [{"name": "sky", "image": "sky.exr", "face_size": 16, "method": "reference"}],
                                   "materials": [{"name": "v", "roughness": 0.5, "sheen_color": [1, 1, 1], "sheen_roughness": 0}]})");
    EXPECT_EQ(reference.probes[0].sheenMethod, MethodKind::reference);
    EXPECT_EQ(reference.probes[0].sheenLevels, (std::vector<int>{0}));
    EXPECT_EQ(reference.probes[0].sheenPyramidLevels, 0);
}

TEST_F(SceneTest, Empty) {
    const Plan p = plan(scene(""));
    EXPECT_TRUE(p.passes().empty());
}

TEST_F(SceneTest, ReferenceMethodReadsNoPyramid) {
    const Plan p = plan(R"({"probes": [{"name": "sky", "image": "sky.exr", "face_size": 16, "method": "reference"}],
                           "materials": [{"name": "plastic", "roughness": 0.5}]})");
    EXPECT_EQ(p.probes[0].pyramidLevels, 0);
}

TEST_F(SceneTest, BadScenesNameTheField) {
    expectRefused(R"({"probes": [{"name": "sky", "image": "missing.exr"}], "materials": []})", "probes[0].image");
    expectRefused(scene(R"({"name": "a", "roughness": 0.5, "shininess": 3})"), "materials[0].shininess");
    expectRefused(scene(R"({"name": "a", "roughness": 1.5})"), "materials[0].roughness");
    expectRefused(scene(R"({"name": "a", "roughness": -0.1})"), "materials[0].roughness");
    expectRefused(scene(R"({"name": "a", "roughness": 0.5}, {"name": "a", "roughness": 0.1})"), "materials[1].name");
    expectRefused(scene(R"({"name": "a"})"), "materials[0].roughness");
    expectRefused(scene(R"({"name": "a", "roughness": 0.5, "probe": "nope"})"), "materials[0].probe");
    expectRefused(scene(R"({"name": "a", "roughness": 0.5, "sheen_color": [1, 1]})"), "materials[0].sheen_color");
    expectRefused(scene(R"({"name": "a", "roughness": 0.5, "sheen_color": [1, 2, 1]})"), "materials[0].sheen_color");
    expectRefused(scene(R"({"name": "a", "roughness": 0.5, "sheen_roughness": 1.5})"), "materials[0].sheen_roughness");
    expectRefused(R"({"probes": [{"name": "sky", "image": "sky.exr", "face_size": 12}], "materials": []})", "probes[0].face_size");
    expectRefused(R"({"probes": [{"name": "sky", "image": "sky.exr", "mapping": "x"}], "materials": []})", "probes[0].mapping");
    expectRefused(R"({"probes": [{"name": "sky", "image": "sky.exr"}], "materials": [], "extra": 1})", "extra");
    expectRefused(R"({"probes": [], "materials": []})", "probes");
    expectRefused("{not json", "not valid JSON");
    expectRefused(R"({"version": 2, "probes": [{"name": "sky", "image": "sky.exr"}], "materials": []})", "version");
}

TEST_F(SceneTest, VersionOneIsTheFormatAndMayBeLeftOut) {
    EXPECT_EQ(readScene(write(R"({"version": 1, "probes": [{"name": "sky", "image": "sky.exr"}], "materials": []})")).probes.size(), 1u);
    EXPECT_EQ(readScene(write(R"({"probes": [{"name": "sky", "image": "sky.exr"}], "materials": []})")).probes.size(), 1u);
}
