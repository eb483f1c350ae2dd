// tools/shader_stats on RADV's null device for RDNA2 (navi21): every pipeline of the runtime compiles
// with statistics, and the per-tap and per-sample costs measured from the instruction counts are
// consistent with what the shaders do. Skipped where the RADV driver is not installed.
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <set>

#include <gtest/gtest.h>

#include "shader_stats.h"

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
            EXPECT_TRUE(names.count(std::string("importance_sampling_") + sampling + "_" + format)) << sampling << " " << format;
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
    const LoopCost hardware = loop("importance_sampling_hardware_rgba32f");
    const LoopCost exact = loop("importance_sampling_exact_rgba32f");
    EXPECT_GT(hardware.instructionsPerUnit(), 0.0);
    EXPECT_LT(hardware.instructionsPerUnit(), exact.instructionsPerUnit());
    EXPECT_LT(hardware.runtimeInstructionsPerUnit(), exact.runtimeInstructionsPerUnit());
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

} // namespace
