// Roughness mappings: the named curves invert, a custom list is refused unless it is a valid
// roughness per level, holds its values exactly, inverts piecewise linearly and travels through
// tables, headers and scenes.
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "probe/error.h"
#include "probe/plan.h"
#include "probe/roughness.h"
#include "probe/scene.h"
#include "probe/table_io.h"

using namespace probe;
namespace fs = std::filesystem;

TEST(Roughness, CustomListHoldsItsValues) {
    const RoughnessMapping mapping = parseRoughnessList("0,0.1,0.35,0.7,1");
    EXPECT_EQ(mapping.curve(), RoughnessMapping::Curve::custom);
    EXPECT_EQ(roughnessMappingName(mapping), "custom");
    EXPECT_EQ(describeRoughnessMapping(mapping), "custom 0,0.1,0.35,0.7,1");
    EXPECT_EQ(mappingOptions(mapping), "--roughness 0,0.1,0.35,0.7,1");
    EXPECT_EQ(mappingOptions(RoughnessMapping::unity), "--mapping unity");
    EXPECT_EQ(levelRoughness(mapping, 2, 5), 0.35);
    EXPECT_DOUBLE_EQ(levelAlpha(mapping, 3, 5), 0.49);
    // The inverse: each level's own roughness, linear between levels, clamped at the ends.
    for (int m = 0; m < 5; ++m) EXPECT_DOUBLE_EQ(roughnessToLevel(mapping, levelRoughness(mapping, m, 5), 5), m);
    EXPECT_DOUBLE_EQ(roughnessToLevel(mapping, 0.225, 5), 1.5);
    EXPECT_DOUBLE_EQ(roughnessToLevel(mapping, 0.5, 5), 2.0 + 0.15 / 0.35);
    const RoughnessMapping rough = parseRoughnessList("0.2,0.6");
    EXPECT_EQ(roughnessToLevel(rough, 0.05, 2), 0.0);
    EXPECT_EQ(roughnessToLevel(rough, 0.9, 2), 1.0);
    EXPECT_EQ(levelsReadForRoughness(mapping, 0.35, 5), (std::vector<int>{2}));
    EXPECT_EQ(levelsReadForRoughness(mapping, 0.5, 5), (std::vector<int>{2, 3}));
    // Equal lists are the same mapping; a named curve is never a list.
    EXPECT_EQ(mapping, RoughnessMapping::custom({0, 0.1, 0.35, 0.7, 1}));
    EXPECT_NE(mapping, RoughnessMapping::custom({0, 0.1, 0.35, 0.7, 0.9}));
    EXPECT_NE(parseRoughnessList("0,0.5,1"), RoughnessMapping::gltf);
}

// The library names its own settings in its errors; the tools name them by their flags, through
// the one table (parameter_flags checks that every name the library throws is placed in it).
TEST(Roughness, ParameterErrorsAreNamedByTheirFlagOnTheCommandLine) {
    EXPECT_EQ(messageWithFlag(ParameterError("roughness", "'a,b': expected numbers")), "--roughness 'a,b': expected numbers");
    EXPECT_EQ(messageWithFlag(ParameterError("method.fis.bias", "9: must be a number")), "--fis-bias 9: must be a number");
    EXPECT_EQ(messageWithFlag(ParameterError("outputFormat", "rgb8: expected")), "--format rgb8: expected");
    EXPECT_EQ(messageWithFlag(ParameterError("pyramidDepth", "9: a 16^2 pyramid")), "pyramidDepth 9: a 16^2 pyramid");
    EXPECT_EQ(parameterFlag("levels"), "");
}

TEST(Roughness, BadListsAreRefused) {
    for (const char* text : {"", ",", "0,,1", "0,0.5,", "a,b", "0;0.5", "0,0.5x", "nan", "0,inf", "1.5", "-0.1,0.5", "0,0.5,0.5", "0.6,0.5",
                             "0,0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8,0.85,0.9,0.95,1"}) {
        try {
            parseRoughnessList(text);
            ADD_FAILURE() << "accepted '" << text << "'";
        } catch (const ParameterError& e) {
            EXPECT_EQ(e.parameter, "roughness") << text;
        }
    }
    EXPECT_THROW(mappingFromOptions("gltf", "0,1"), ProbeError);
    EXPECT_EQ(mappingFromOptions("", ""), RoughnessMapping::gltf);
    EXPECT_EQ(mappingFromOptions("filament", ""), RoughnessMapping::filament);
}

TEST(Roughness, LevelCountFollowsTheList) {
    const RoughnessMapping mapping = parseRoughnessList("0,0.3,0.6,1");
    EXPECT_EQ(chooseLevelCount(64, std::nullopt, mapping), 4);
    EXPECT_EQ(chooseLevelCount(64, 4, mapping), 4);
    EXPECT_THROW(chooseLevelCount(64, 5, mapping), ParameterError);
    EXPECT_THROW(chooseLevelCount(4, std::nullopt, mapping), ProbeError); // 4 levels: a 4^2 face has 3
    EXPECT_EQ(chooseLevelCount(64, std::nullopt, RoughnessMapping::gltf), 6);
    EXPECT_THROW(levelRoughness(mapping, 1, 5), ParameterError);
    EXPECT_THROW(emptyTable(16, 3, 4, TableForm::quadratic, mapping, {}), ProbeError);
}

TEST(Roughness, CustomTableRoundTrips) {
    const RoughnessMapping mapping = parseRoughnessList("0.05,0.3,0.6,1");
    TapTable table = emptyTable(16, 4, 4, TableForm::constant, mapping, {});
    // Every tap along its frame's axis, weight 1: a valid filter.
    for (TableLevel& level : table.levels)
        for (int f = 0; f < kFrameCount; ++f)
            for (int t = 0; t < table.taps; ++t) {
                level.coefficients[table.offset(f, t, 2)] = 1.0;
                level.coefficients[table.offset(f, t, tapWeight)] = 1.0;
            }
    const fs::path dir = fs::temp_directory_path() / fmt::format("roughness_test_{}", ::getpid());
    fs::create_directories(dir);
    std::ofstream(dir / "custom.json") << tableToJson(table);
    const TapTable back = readTable(dir / "custom.json");
    EXPECT_EQ(back.mapping, mapping);
    EXPECT_DOUBLE_EQ(tableLevelAlpha(back, 0), 0.0025);
    // The header carries the list, so that a compiled-in table keeps it.
    const std::string header = tableCppHeader(table, "custom16");
    EXPECT_NE(header.find("kMapping = \"custom\""), std::string::npos);
    EXPECT_NE(header.find("kLevelRoughness[4] = {0.05, 0.3, 0.6, 1}"), std::string::npos) << header;
    // "roughness" belongs to a custom mapping only; the list must be valid.
    TapTable named = table;
    named.mapping = RoughnessMapping::gltf;
    std::string text = tableToJson(named);
    text.insert(1, "\"roughness\": [0, 0.3, 0.6, 1],");
    std::ofstream(dir / "named.json") << text;
    EXPECT_THROW(readTable(dir / "named.json"), ProbeError);
    text = tableToJson(table);
    const std::size_t at = text.find("0.6");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 3, "0.2");
    std::ofstream(dir / "decreasing.json") << text;
    try {
        readTable(dir / "decreasing.json");
        ADD_FAILURE() << "a decreasing list was read";
    } catch (const ProbeError& e) {
        EXPECT_NE(std::string(e.what()).find("decreasing.json"), std::string::npos) << e.what();
    }
    fs::remove_all(dir);
}

TEST(Roughness, SceneTakesAList) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("roughness_scene_{}", ::getpid());
    fs::create_directories(dir);
    std::ofstream(dir / "sky.exr") << "";
    const auto read = [&](const std::string& probe) {
        std::ofstream(dir / "scene.json") << fmt::format(R"({{"probes": [{{"name": "sky", "image": "sky.exr", "face_size": 16{}}}],
                                                            "materials": [{{"name": "a", "roughness": 0.5}}]}})",
                                                         probe);
        return readScene(dir / "scene.json");
    };
    const Scene scene = read(R"(, "roughness": [0, 0.4, 1])");
    EXPECT_EQ(scene.probes[0].levelCount, 3);
    EXPECT_EQ(scene.probes[0].mapping, RoughnessMapping::custom({0, 0.4, 1}));
    for (const char* bad : {R"(, "roughness": [0, 0.4, 1], "mapping": "gltf")", R"(, "roughness": [0, 0.4, 1], "levels": 4)",
                            R"(, "roughness": [0.4, 0.2])", R"(, "roughness": "0,1")", R"(, "roughness": [])"}) {
        try {
            read(bad);
            ADD_FAILURE() << "accepted " << bad;
        } catch (const ProbeError& e) {
            EXPECT_NE(std::string(e.what()).find("probes[0]."), std::string::npos) << e.what();
        }
    }
    fs::remove_all(dir);
}
