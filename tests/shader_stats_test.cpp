// bench/shader_stats/shader_stats on RADV's null device for RDNA2 (navi21): every pipeline of the runtime compiles
// with statistics, the per-tap and per-sample costs measured from the instruction counts are
// consistent with what the shaders do, and a sweep's methods are costed with their own shader.
// Skipped where the RADV driver is not installed.
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <set>

#include <gtest/gtest.h>

#include "probe/error.h"
#include "shader_stats.h"
#include "sweep_instructions.h"

namespace {

using probe::stats::LoopCost;
using probe::stats::PipelineStatistics;

class ShaderStatsTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        if (!std::filesystem::exists(PROBE_RADV_ICD)) return;
        // Before the first Vulkan call of the process: the loader reads them when it loads drivers.
        setenv("VK_ICD_FILENAMES", PROBE_RADV_ICD, 1);
        setenv("RADV_FORCE_FAMILY", "navi21", 1);
        device = std::make_unique<probe::stats::StatisticsDevice>();
    }
    static void TearDownTestSuite() { device.reset(); }
    void SetUp() override {
        if (!device) GTEST_SKIP() << PROBE_RADV_ICD << " is not installed (Debian: mesa-vulkan-drivers)";
    }

    // The measured loop of this name.
    static LoopCost loop(const std::string& name) {
        for (const probe::stats::LoopVariant& v : probe::stats::loopVariants())
            if (v.name == name) return probe::stats::measureLoop(*device, v);
        ADD_FAILURE() << "no loop " << name;
        return {};
    }

    static inline std::unique_ptr<probe::stats::StatisticsDevice> device;
};

TEST_F(ShaderStatsTest, EveryRuntimePipelineCompilesWithStatistics) {
    EXPECT_NE(device->name().find("NAVI21"), std::string::npos) << device->name();
    const std::vector<probe::stats::ShaderVariant> variants = probe::stats::runtimeVariants();
    std::set<std::string> names;
    for (const probe::stats::ShaderVariant& v : variants) {
        EXPECT_TRUE(names.insert(v.name).second) << "listed twice: " << v.name;
        const PipelineStatistics s = device->compile(v.spirv, v.specialization);
        EXPECT_GT(s.instructions, 0) << v.name;
        EXPECT_GT(s.vgprs, 0) << v.name;
        EXPECT_GT(s.sgprs, 0) << v.name;
        EXPECT_GT(s.latency, 0) << v.name;
        EXPECT_GT(s.inverseThroughput, 0) << v.name;
        EXPECT_EQ(s.spilledVgprs, 0) << v.name;
        EXPECT_EQ(s.spilledSgprs, 0) << v.name;
    }
    // Both sampling paths of both filters, with every output format, quad and constant tables.
    for (const char* sampling : {"hardware", "exact"})
        for (const char* format : {"rgba32f", "rgba16f", "b10g11r11"}) {
            EXPECT_TRUE(names.count(std::string("fis_") + sampling + "_" + format)) << sampling << " " << format;
            for (const char* form : {"quad", "const"})
                EXPECT_TRUE(names.count(std::string("table_filter_") + sampling + "_" + format + " " + form)) << sampling << " " << format;
        }
}

// A tap or sample read through the sampler costs fewer instructions than the shader's own trilinear
// arithmetic; a quad table's tap evaluates three coefficients where a constant table's reads one.
TEST_F(ShaderStatsTest, HardwareSamplingCostsLessPerTapAndSample) {
    for (const char* form : {"quad", "const"}) {
        const LoopCost hardware = loop(std::string("table_filter_hardware_rgba32f ") + form);
        const LoopCost exact = loop(std::string("table_filter_exact_rgba32f ") + form);
        EXPECT_GT(hardware.instructionsPerUnit(), 0.0) << form;
        EXPECT_LT(hardware.instructionsPerUnit(), exact.instructionsPerUnit()) << form;
        EXPECT_LT(hardware.runtimeInstructionsPerUnit(), exact.runtimeInstructionsPerUnit()) << form;
    }
    EXPECT_GT(loop("table_filter_hardware_rgba32f quad").instructionsPerUnit(),
              loop("table_filter_hardware_rgba32f const").instructionsPerUnit());
    const LoopCost hardware = loop("fis_hardware_rgba32f");
    const LoopCost exact = loop("fis_exact_rgba32f");
    EXPECT_GT(hardware.instructionsPerUnit(), 0.0);
    EXPECT_LT(hardware.instructionsPerUnit(), exact.instructionsPerUnit());
    EXPECT_LT(hardware.runtimeInstructionsPerUnit(), exact.runtimeInstructionsPerUnit());
}

// With hardware sampling a tap or sample is one vector memory instruction, its image sample: the
// table's coefficients and FIS's samples, the same for a whole workgroup, come through scalar loads
// (the storage buffer of buffers.glsl, a face per workgroup). Exact sampling reads its eight texels
// through the texel buffer.
TEST_F(ShaderStatsTest, HardwareTapAndSampleReadOnlyThePyramidThroughVectorMemory) {
    for (const char* name : {"table_filter_hardware_rgba32f quad", "table_filter_hardware_rgba32f const", "fis_hardware_rgba32f"}) {
        const LoopCost cost = loop(name);
        EXPECT_GT(cost.runtime.vectorMemory, 0) << name;
        EXPECT_EQ(cost.vectorMemoryPerUnit(), 1.0) << name;
    }
    EXPECT_GE(loop("table_filter_exact_rgba32f quad").vectorMemoryPerUnit(), 8.0);
}

// The engine drop-in takes its face, and so its frames' axes, from the workgroup: its constant table
// then comes through scalar loads too, and its vector memory instructions are the body of its rolled
// tap loop, three frames of four image samples, and the output's store.
TEST_F(ShaderStatsTest, EngineDropInReadsOnlyThePyramidThroughVectorMemory) {
    for (const probe::stats::ShaderVariant& v : probe::stats::runtimeVariants())
        if (v.name == "engine/probe_table_filter gltf128_quad8") {
            EXPECT_EQ(device->compile(v.spirv, v.specialization).vectorMemory, 3 * 4 + 1);
            return;
        }
    ADD_FAILURE() << "no engine drop-in among the variants";
}

// The engine drop-in pyramid pass reads four bilinear taps and stores one texel, and costs no more
// than the runtime's B-spline pass over the same cube image, which also copies the source at level 0.
TEST_F(ShaderStatsTest, EngineDropInPyramidCostsNoMoreThanTheRuntimePass) {
    const auto compiled = [&](const std::string& name) {
        for (const probe::stats::ShaderVariant& v : probe::stats::runtimeVariants())
            if (v.name == name) return device->compile(v.spirv, v.specialization);
        ADD_FAILURE() << "no variant " << name;
        return probe::stats::PipelineStatistics{};
    };
    const probe::stats::PipelineStatistics dropIn = compiled("engine/probe_pyramid gltf128_quad8");
    const probe::stats::PipelineStatistics runtime = compiled("pyramid_image_rgba32f bspline");
    EXPECT_EQ(dropIn.vectorMemory, 4 + 1);
    EXPECT_LE(dropIn.instructions, runtime.instructions);
    EXPECT_LE(dropIn.vgprs, runtime.vgprs);
}

// The fixed counts unroll (the code grows with the count), and the runtime's loop costs at least the
// unrolled body and less than twice it.
TEST_F(ShaderStatsTest, FixedCountsUnrollAndBoundTheRuntimeLoop) {
    for (const probe::stats::LoopVariant& v : probe::stats::loopVariants()) {
        const LoopCost cost = probe::stats::measureLoop(*device, v);
        EXPECT_GT(cost.b.instructions, cost.a.instructions) << v.name;
        EXPECT_GT(cost.fixedInstructions(), 0.0) << v.name;
        EXPECT_GE(cost.runtimeInstructionsPerUnit(), cost.instructionsPerUnit()) << v.name;
        EXPECT_LT(cost.runtimeInstructionsPerUnit(), 2.0 * cost.instructionsPerUnit()) << v.name;
    }
}

// A table row and an FIS row of a sweep report, costed by hand from the three compilations' raw
// instruction counts: the loop body from the two unrolled counts, the code outside it, the runtime
// loop per tap or sample, then that code once and the loop per tap or sample per texel.
TEST_F(ShaderStatsTest, SweepMethodsCostTheirShaderPerTexel) {
    std::vector<LoopCost> costs;
    for (const probe::stats::LoopVariant& v : probe::stats::loopVariants()) costs.push_back(probe::stats::measureLoop(*device, v));
    const auto byHand = [&](const std::string& name, double taps) {
        for (const LoopCost& c : costs)
            if (c.loop.name == name) {
                const double body = double(c.b.instructions - c.a.instructions) / (c.loop.unitsB - c.loop.unitsA);
                const double outside = double(c.a.instructions) - c.loop.unitsA * body;
                const double perUnit = (double(c.runtime.instructions) - outside) / c.loop.unitsPerIteration;
                return outside + taps * perUnit;
            }
        ADD_FAILURE() << "no loop " << name;
        return 0.0;
    };
    const nlohmann::json report = {
        {"methods",
         {{{"method", "gltf128_quad8"}, {"family", "table"}, {"form", "quad"}, {"shader_taps_per_texel", 19.5}},
          {{"method", "gltf128_const4"}, {"family", "table"}, {"form", "const"}, {"shader_taps_per_texel", 9.75}},
          {{"method", "fis32-bias0-bspline"}, {"family", "fis"}, {"form", ""}, {"shader_taps_per_texel", 31.3}},
          {{"method", "fismix8-bias0-box"}, {"family", "fis-mix"}, {"form", ""}, {"shader_taps_per_texel", 14.2}},
          {{"method", "fisparaboloid32-bias0"}, {"family", "fis-paraboloid"}, {"form", ""}, {"shader_taps_per_texel", 31.3}}}}};
    const nlohmann::json out = probe::stats::sweepInstructions(report, costs, device->name(), device->driver());
    const std::vector<std::pair<std::string, double>> expected{{"table_filter_hardware_rgba32f quad", 19.5},
                                                               {"table_filter_hardware_rgba32f const", 9.75},
                                                               {"fis_hardware_rgba32f", 31.3},
                                                               {"fis_hardware_rgba32f", 14.2},
                                                               {"fis_paraboloid_rgba32f", 31.3}};
    ASSERT_EQ(out["methods"].size(), expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) {
        const nlohmann::json& m = out["methods"][k];
        EXPECT_EQ(m["loop"], expected[k].first) << m["method"];
        EXPECT_NEAR(m["instructions_per_texel"].get<double>(), byHand(expected[k].first, expected[k].second), 1e-9) << m["method"];
    }
    // The table with N = 8 costs more per texel than FIS with as many samples as its taps, and less than
    // exact sampling would.
    EXPECT_GT(out["methods"][0]["instructions_per_texel"].get<double>(), byHand("fis_hardware_rgba32f", 19.5));
    EXPECT_LT(out["methods"][0]["instructions_per_texel"].get<double>(), byHand("table_filter_exact_rgba32f quad", 19.5));

    EXPECT_THROW(probe::stats::sweepMethodLoop("table", "cubic"), probe::ProbeError);
    EXPECT_THROW(probe::stats::sweepMethodLoop("reference", ""), probe::ProbeError);
    const nlohmann::json missing = {{"methods", {{{"method", "old"}, {"family", "table"}, {"shader_taps_per_texel", 8.0}}}}};
    try {
        probe::stats::sweepInstructions(missing, costs, device->name(), device->driver());
        ADD_FAILURE() << "a method without its form was costed";
    } catch (const probe::ProbeError& e) {
        EXPECT_NE(std::string(e.what()).find("method old"), std::string::npos) << e.what();
    }
}

} // namespace
