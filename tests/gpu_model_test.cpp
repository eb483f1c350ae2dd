// The GPU passes equal their CPU models (core's pyramid, table filter and importance sampling) on
// random probes and random tables, every level and face; constants stay constant; FIS-1024 is
// close to the reference on a smooth sky.
#include <random>

#include <fmt/format.h>

#include "device.h" // runtime/src: Device::Impl
#include "gpu_test_support.h"
#include "probe/error.h"
#include "probe/error_measures.h"
#include "probe/importance_sampling.h"
#include "probe/pyramid.h"
#include "probe/reference.h"
#include "probe/synthetic.h"
#include "probe/table_filter.h"

using namespace probe;
using probetest::GpuTest;

namespace {

// Every bilinear read is the shader's own float arithmetic on the same texels as the double CPU
// model; the differences are float rounding of positions (~1e-7 texel), weights and sums.
constexpr double kModelTolerance = 1e-5;

const PyramidSettings kAllPyramids[] = {
    {PyramidKind::bspline, PyramidWeighting::solidAngle},
    {PyramidKind::bspline, PyramidWeighting::inverseSolidAngle},
    {PyramidKind::box, PyramidWeighting::solidAngle},
    {PyramidKind::box, PyramidWeighting::inverseSolidAngle},
};

std::string describe(const PyramidSettings& p) { return fmt::format("{} {}", pyramidKindName(p.kind), pyramidWeightingName(p.weighting)); }

// A random table shaped like a real one: per level, taps around the frame's z axis spread with the
// lobe, levels near the output level, positive weights, small quadratic terms.
TapTable randomTable(int size, int levels, int taps, TableForm form, RoughnessMapping mapping, PyramidSettings pyramid, unsigned seed) {
    TapTable table = emptyTable(size, levels, taps, form, mapping, pyramid);
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const int k = coefficientCount(form);
    for (int m = 0; m < levels; ++m) {
        const double spread = 0.1 + levelAlpha(mapping, m, levels);
        for (int frame = 0; frame < kFrameCount; ++frame)
            for (int t = 0; t < taps; ++t) {
                double* c = &table.levels[m].coefficients[table.offset(frame, t)];
                const double base[kTapParameterCount] = {spread * unit(random), spread * unit(random), 1.0, m + 0.8 * unit(random),
                                                         1.0 + 0.5 * unit(random)};
                for (int p = 0; p < kTapParameterCount; ++p) {
                    c[p * k] = base[p];
                    for (int q = 1; q < k; ++q) c[p * k + q] = 0.1 * spread * unit(random);
                }
            }
    }
    return table;
}

gpu::FilterSettings settingsFor(gpu::Method method, int size, int levels, RoughnessMapping mapping, PyramidSettings pyramid) {
    gpu::FilterSettings s;
    s.method = method;
    s.faceSize = size;
    s.levelCount = levels;
    s.mapping = mapping;
    s.pyramid = pyramid;
    return s;
}

void expectLevelsEqual(const CubeLevels& gpuLevels, const CubeLevels& cpuLevels, double tolerance, const std::string& what) {
    ASSERT_EQ(gpuLevels.size(), cpuLevels.size()) << what;
    for (std::size_t m = 0; m < cpuLevels.size(); ++m) {
        const double error = probetest::maxRelativeError(gpuLevels[m], cpuLevels[m]);
        ::testing::Test::RecordProperty(fmt::format("{} level {}", what, m), fmt::format("{:.3g}", error));
        EXPECT_LT(error, tolerance) << what << ", level " << m;
    }
}

} // namespace

TEST_F(GpuTest, PyramidEqualsCpuModel) {
    const CubeImage source = probetest::randomProbe(32, 11);
    for (const PyramidSettings& pyramid : kAllPyramids) {
        gpu::Filter filter(probetest::testDevice(), settingsFor(gpu::Method::fis, 32, 5, RoughnessMapping::gltf, pyramid));
        filter.run(source);
        expectLevelsEqual(filter.downloadPyramid(), buildPyramid(source, pyramid), kModelTolerance, "pyramid " + describe(pyramid));
    }
}

TEST_F(GpuTest, ConstantProbeStaysConstantInEveryPyramidLevel) {
    const glm::vec3 radiance(0.25f, 1.0f, 3.0f);
    for (const PyramidSettings& pyramid : kAllPyramids) {
        gpu::Filter filter(probetest::testDevice(), settingsFor(gpu::Method::fis, 64, 6, RoughnessMapping::gltf, pyramid));
        filter.run(constantProbe(64, radiance));
        const CubeLevels levels = filter.downloadPyramid();
        ASSERT_EQ(levels.size(), 7u);
        for (const CubeImage& level : levels)
            EXPECT_LT(probetest::maxRelativeError(level, CubeImage(level.size, radiance)), 1e-6)
                << describe(pyramid) << ", size " << level.size;
    }
}

TEST_F(GpuTest, TableFilterEqualsCpuModel) {
    struct Case {
        int size;
        TableForm form;
        RoughnessMapping mapping;
        PyramidSettings pyramid;
    };
    const Case cases[] = {
        {32, TableForm::quadratic, RoughnessMapping::gltf, kAllPyramids[0]},
        {32, TableForm::constant, RoughnessMapping::authors, kAllPyramids[0]},
        {16, TableForm::quadratic, RoughnessMapping::authors, kAllPyramids[3]},
    };
    unsigned seed = 20;
    for (const Case& c : cases) {
        const int levels = defaultLevelCount(c.size);
        const TapTable table = randomTable(c.size, levels, 8, c.form, c.mapping, c.pyramid, seed++);
        const CubeImage source = probetest::randomProbe(c.size, seed++);
        gpu::FilterSettings s = settingsFor(gpu::Method::table, c.size, levels, c.mapping, c.pyramid);
        s.table = &table;
        gpu::Filter filter(probetest::testDevice(), s);
        expectLevelsEqual(filter.run(source), tableFilter(source, table), kModelTolerance,
                          fmt::format("table {} {}^2 {}", tableFormName(c.form), c.size, roughnessMappingName(c.mapping)));
    }
}

// A table whose levels use fewer taps than it holds (probefit mix): the GPU stops at the tap groups
// in use, the CPU model at probe::tapsInUse; levels 1 and 2 keep 4 and 9 of 16 taps (9: a partly
// used group of four).
TEST_F(GpuTest, PaddedTableEqualsCpuModel) {
    TapTable table = randomTable(32, 5, 16, TableForm::quadratic, RoughnessMapping::gltf, kAllPyramids[0], 23);
    const int kept[] = {16, 4, 9, 16, 16};
    for (int m = 0; m < 5; ++m)
        for (int frame = 0; frame < kFrameCount; ++frame)
            for (int t = kept[m]; t < 16; ++t)
                for (int q = 0; q < 3; ++q) table.levels[m].coefficients[table.offset(frame, t, tapWeight) + q] = 0.0;
    for (int m = 0; m < 5; ++m) EXPECT_EQ(tapsInUse(table, m), kept[m]) << "level " << m;
    const CubeImage source = probetest::randomProbe(32, 24);
    gpu::FilterSettings s = settingsFor(gpu::Method::table, 32, 5, RoughnessMapping::gltf, kAllPyramids[0]);
    s.table = &table;
    gpu::Filter filter(probetest::testDevice(), s);
    expectLevelsEqual(filter.run(source), tableFilter(source, table), kModelTolerance, "padded table");
}

TEST_F(GpuTest, ImportanceSamplingEqualsCpuModel) {
    struct Case {
        int samples;
        double bias;
        RoughnessMapping mapping;
        PyramidSettings pyramid;
    };
    const Case cases[] = {
        {32, 0.0, RoughnessMapping::gltf, kAllPyramids[0]},
        {64, 1.0, RoughnessMapping::authors, kAllPyramids[2]},
        {16, 0.5, RoughnessMapping::filament, kAllPyramids[1]},
    };
    const CubeImage source = probetest::randomProbe(32, 30);
    for (const Case& c : cases) {
        gpu::FilterSettings s = settingsFor(gpu::Method::fis, 32, 5, c.mapping, c.pyramid);
        s.fisSamples = c.samples;
        s.fisBias = c.bias;
        gpu::Filter filter(probetest::testDevice(), s);
        const ImportanceSamplingSettings cpu{c.samples, c.bias, c.pyramid, {}};
        expectLevelsEqual(filter.run(source), importanceSampleFilter(source, 5, c.mapping, cpu), kModelTolerance,
                          fmt::format("fis {} bias {} {}", c.samples, c.bias, roughnessMappingName(c.mapping)));
    }
}

// Per-level sample counts (the sweep's FIS mixes): each level as FIS with that level's count.
TEST_F(GpuTest, ImportanceSamplingPerLevelEqualsCpuModel) {
    const CubeImage source = probetest::randomProbe(32, 31);
    gpu::FilterSettings s = settingsFor(gpu::Method::fis, 32, 5, RoughnessMapping::gltf, kAllPyramids[0]);
    s.fisSamples = 8;
    s.fisLevelSamples = {1, 8, 3, 64, 256};
    gpu::Filter filter(probetest::testDevice(), s);
    const CubeLevels levels = filter.run(source);
    for (int m = 1; m < 5; ++m) {
        const ImportanceSamplingSettings uniform{s.fisLevelSamples[m], 0.0, kAllPyramids[0], {}};
        expectLevelsEqual({levels[m]}, {importanceSampleFilter(source, 5, RoughnessMapping::gltf, uniform)[m]}, kModelTolerance,
                          fmt::format("fis level {} with {} samples", m, s.fisLevelSamples[m]));
    }
    s.fisLevelSamples = {8, 8, 8};
    EXPECT_THROW(gpu::Filter(probetest::testDevice(), s), ProbeError);
    s.fisLevelSamples = {8, 8, 0, 8, 8};
    EXPECT_THROW(gpu::Filter(probetest::testDevice(), s), ProbeError);
}

TEST_F(GpuTest, WhiteFurnaceEveryMethod) {
    const glm::vec3 radiance(0.25f, 1.0f, 3.0f);
    const CubeImage constant = constantProbe(32, radiance);
    const TapTable table = randomTable(32, 5, 8, TableForm::quadratic, RoughnessMapping::gltf, kAllPyramids[0], 40);
    for (gpu::Method method : {gpu::Method::table, gpu::Method::fis, gpu::Method::reference}) {
        gpu::FilterSettings s = settingsFor(method, 32, 5, RoughnessMapping::gltf, kAllPyramids[0]);
        s.table = &table;
        gpu::Filter filter(probetest::testDevice(), s);
        const CubeLevels levels = filter.run(constant);
        for (int m = 0; m < 5; ++m)
            EXPECT_LT(probetest::maxRelativeError(levels[m], CubeImage(32 >> m, radiance)), 1e-5)
                << gpu::methodName(method) << ", level " << m;
    }
}

// FIS with 1024 samples and bias 0 over the B-spline pyramid is within 3% image L1 of the
// reference at every filtered level of a smooth sky.
TEST_F(GpuTest, ImportanceSampling1024NearReferenceOnSky) {
    const int size = 64, levels = defaultLevelCount(size);
    const CubeImage sky = skyProbe(size);
    gpu::FilterSettings s = settingsFor(gpu::Method::fis, size, levels, RoughnessMapping::gltf, kAllPyramids[0]);
    s.fisSamples = 1024;
    gpu::Filter filter(probetest::testDevice(), s);
    const CubeLevels fis = filter.run(sky);
    const CubeLevels reference = referenceFilter(sky, levels, RoughnessMapping::gltf);
    for (int m = 1; m < levels; ++m) {
        const double error = imageL1(fis[m], reference[m]);
        ::testing::Test::RecordProperty(fmt::format("level{}_image_l1", m), fmt::format("{:.4f}", error));
        EXPECT_LT(error, 0.03) << "level " << m;
    }
}

// The table shader takes a texel's third frame per subgroup (subgroupAny): on a device without
// subgroup vote in compute shaders the table method is refused, naming the device; FIS still runs.
TEST_F(GpuTest, TableMethodNeedsSubgroupVote) {
    const gpu::Device& shared = probetest::testDevice();
    const gpu::Device device(shared.instance(), shared.physicalDevice(), shared.device(), shared.queueFamily(), shared.queue());
    device.impl().computeSubgroupVote = false; // what a device without it reports
    const TapTable table = randomTable(16, 4, 4, TableForm::quadratic, RoughnessMapping::gltf, kAllPyramids[0], 50);
    gpu::FilterSettings s = settingsFor(gpu::Method::table, 16, 4, RoughnessMapping::gltf, kAllPyramids[0]);
    s.table = &table;
    try {
        gpu::Filter filter(device, s);
        ADD_FAILURE() << "the table method was not refused";
    } catch (const ProbeError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("subgroup vote"), std::string::npos) << message;
        EXPECT_NE(message.find(device.info().name), std::string::npos) << message;
    }
    s.method = gpu::Method::fis;
    EXPECT_NO_THROW(gpu::Filter(device, s));
}
