// Impulse responses measured on the GPU: one run per source texel and channel (an impulse probe)
// gives every output texel's weights over the source texels, hence the impulse-response L1 of
// docs/design.md against the reference lobe, level by level. It must equal what the CPU model says
// (core's table and FIS impulse forms), so that what the optimizer minimizes is what the shader does.
#include <fmt/format.h>

#include "gpu_test_support.h"
#include "probe/cpu_filter.h"
#include "probe/error_measures.h"
#include "probe/fis.h"
#include "probe/reference.h"
#include "probe/table_filter.h"
#include "probe/table_io.h"

using namespace probe;
using probetest::GpuTest;

namespace {

constexpr int kSize = 16;

// weights[m][outputTexel][sourceTexel] from GPU runs on impulse probes, three impulses per run
// (one per channel: the filters are linear and act on channels independently). Each impulse sits
// on a constant 1, which the normalized filters keep, so that a negative weight (tables may have
// them) survives the output's clamp to >= 0: weight = output - 1.
std::vector<std::vector<std::vector<double>>> gpuImpulseResponses(gpu::Filter& filter, int levels) {
    const std::size_t sources = texelCount(kSize);
    std::vector<std::vector<std::vector<double>>> weights(static_cast<std::size_t>(levels));
    for (int m = 0; m < levels; ++m) weights[m].assign(texelCount(kSize >> m), std::vector<double>(sources, 0.0));
    for (std::size_t first = 0; first < sources; first += 3) {
        CubeImage probe(kSize, glm::vec3(1.0f));
        for (std::size_t c = 0; c < 3 && first + c < sources; ++c) probe.rgb[3 * (first + c) + c] = 2.0f;
        const CubeLevels out = filter.run(probe);
        for (int m = 0; m < levels; ++m)
            for (std::size_t t = 0; t < texelCount(kSize >> m); ++t)
                for (std::size_t c = 0; c < 3 && first + c < sources; ++c) weights[m][t][first + c] = double(out[m].rgb[3 * t + c]) - 1.0;
    }
    return weights;
}

using Response = std::function<std::vector<double>(int level, const Texel& texel)>;

// Per filtered level, the solid-angle weighted mean and the worst impulse L1 over every output
// texel of a method given by its impulse responses.
std::vector<ImpulseError> impulseL1PerLevel(int levels, const RoughnessMapping& mapping, const Response& response) {
    std::vector<ImpulseError> errors(static_cast<std::size_t>(levels));
    for (int m = 0; m < levels; ++m) {
        const double alpha = levelAlpha(mapping, m, levels);
        if (alpha <= 0.0) continue;
        const int size = kSize >> m;
        const CubeGeometry geometry(size);
        ImpulseErrorAccumulator accumulator;
        for (std::size_t t = 0; t < texelCount(size); ++t) {
            const Texel texel{int(t / (size * size)), int(t % size), int(t / size % size)};
            accumulator.add(texel, geometry.solidAngles[t],
                            impulseL1(response(m, texel), referenceKernel(geometry.directions[t], kSize, {Lobe::ggx, alpha})));
        }
        errors[m] = accumulator.result();
    }
    return errors;
}

std::vector<ImpulseError> gpuImpulseL1(gpu::Filter& filter, int levels, const RoughnessMapping& mapping) {
    const auto weights = gpuImpulseResponses(filter, levels);
    return impulseL1PerLevel(levels, mapping, [&](int m, const Texel& texel) { return weights[m][texelIndex(texel, kSize >> m)]; });
}

// Per filtered level, the impulse L1 over every output texel measured on the GPU and by the CPU
// model; they agree within 1e-3 (the GPU's float weights against the model's double ones).
void expectImpulseL1Matches(gpu::Filter& filter, int levels, const RoughnessMapping& mapping, const Response& model,
                            const std::string& what) {
    const std::vector<ImpulseError> gpuErrors = gpuImpulseL1(filter, levels, mapping);
    const std::vector<ImpulseError> cpuErrors = impulseL1PerLevel(levels, mapping, model);
    for (int m = 0; m < levels; ++m) {
        if (levelAlpha(mapping, m, levels) <= 0.0) continue;
        const ImpulseError g = gpuErrors[m], c = cpuErrors[m];
        ::testing::Test::RecordProperty(fmt::format("{} level {} L1 gpu/cpu", what, m), fmt::format("{:.5f}/{:.5f}", g.mean, c.mean));
        EXPECT_NEAR(g.mean, c.mean, 1e-3) << what << ", level " << m;
        EXPECT_NEAR(g.max, c.max, 1e-3) << what << ", level " << m << " (worst texel)";
    }
}

} // namespace

TEST_F(GpuTest, TableImpulseL1EqualsCpuModel) {
    const TapTable table = readTable(PROBE_TEST_FIXTURES "/table_16_quad4_gltf.json");
    ASSERT_EQ(table.faceSize, kSize);
    gpu::Filter filter(probetest::testDevice(), probetest::tableSettings(table));
    const std::vector<DownsampleOperator> operators = pyramidOperators(kSize, table.pyramid);
    expectImpulseL1Matches(
        filter, table.levelCount, table.mapping,
        [&](int level, const Texel& texel) { return tableImpulseResponse(table, operators, level, texel); }, "table fixture");
}

TEST_F(GpuTest, FisImpulseL1EqualsCpuModel) {
    const int levels = defaultLevelCount(kSize);
    gpu::FilterSettings s;
    s.method.kind = MethodKind::fis;
    s.faceSize = kSize;
    s.levelCount = levels;
    s.method.fis.samples = 32;
    s.sampling = gpu::Sampling::exact;
    gpu::Filter filter(probetest::testDevice(), s);
    const FisSettings& cpu = s.method.fis;
    const std::vector<DownsampleOperator> operators = pyramidOperators(kSize, s.method.pyramid());
    expectImpulseL1Matches(
        filter, levels, s.mapping,
        [&](int level, const Texel& texel) { return fisImpulseResponse(operators, kSize, levels, s.mapping, cpu, level, texel); },
        "fis 32");
}

// What probefit eval recorded for a committed table (over every output texel of all six faces)
// is what the shader does with it: the L1 measured on the GPU on impulse probes.
TEST_F(GpuTest, CommittedTableImpulseL1EqualsItsRecord) {
    const TapTable table = readTable(PROBE_TEST_TABLES "/gltf16_quad8.json");
    ASSERT_EQ(table.faceSize, kSize);
    gpu::Filter filter(probetest::testDevice(), probetest::tableSettings(table));
    const std::vector<ImpulseError> gpu = gpuImpulseL1(filter, table.levelCount, table.mapping);
    for (int m = 0; m < table.levelCount; ++m) {
        if (tableLevelAlpha(table, m) <= 0.0) continue;
        ASSERT_GE(table.levels[m].all.mean, 0.0) << "level " << m << " has no all-texel record";
        EXPECT_NEAR(gpu[m].mean, table.levels[m].all.mean, 1e-3) << "level " << m;
        EXPECT_NEAR(gpu[m].max, table.levels[m].all.max, 1e-3) << "level " << m << " (worst texel)";
    }
}
