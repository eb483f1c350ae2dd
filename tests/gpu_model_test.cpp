// The GPU passes equal their CPU models (core's pyramid, table filter and importance sampling) on
// random probes and random tables, every level and face, in both sampling modes (exact: to float
// rounding; hardware: within the sampler's precision, gpu_test_support.h); constants stay
// constant; FIS-1024 is close to the reference on a smooth sky.
#include <bit>
#include <limits>
#include <random>

#include <fmt/format.h>

#include "device.h"             // runtime/src: Device::Impl
#include "filter_descriptors.h" // runtime/src: kWideWrittenMipCount
#include "gpu_test_support.h"
#include "probe/cpu_filter.h"
#include "probe/error.h"
#include "probe/error_measures.h"
#include "probe/filter_method.h"
#include "probe/fis.h"
#include "probe/pyramid.h"
#include "probe/reference.h"
#include "probe/shared_constants.h"
#include "probe/synthetic.h"
#include "probe/table_filter.h"

using namespace probe;
using probetest::GpuTest;

namespace {

const PyramidSettings kAllPyramids[] = {
    {PyramidKind::bspline, PyramidWeighting::solidAngle},
    {PyramidKind::bspline, PyramidWeighting::inverseSolidAngle},
    {PyramidKind::box, PyramidWeighting::solidAngle},
    {PyramidKind::box, PyramidWeighting::inverseSolidAngle},
};

std::string describe(const PyramidSettings& p) { return fmt::format("{} {}", pyramidKindName(p.kind), pyramidWeightingName(p.weighting)); }

// A random table shaped like a real one: per level, taps around the frame's z axis spread with the
// lobe, levels near the output level, positive weights, small quadratic terms.
TapTable randomTable(int size, int levels, int taps, TableForm form, const RoughnessMapping& mapping, PyramidSettings pyramid,
                     unsigned seed) {
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

gpu::FilterSettings settingsFor(MethodKind method, int size, int levels, const RoughnessMapping& mapping, PyramidSettings pyramid,
                                gpu::Sampling sampling) {
    gpu::FilterSettings s;
    s.method.kind = method;
    s.method.fis.pyramid = pyramid;
    s.faceSize = size;
    s.levelCount = levels;
    s.mapping = mapping;
    s.sampling = sampling;
    // The model's arithmetic is float32, hardware sampling's pyramid here too: what an RGBA16F one, the
    // default, adds is gpu_format_test.cpp's.
    if (sampling == gpu::Sampling::hardware && method != MethodKind::reference) s.pyramidFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    return s;
}

std::string describe(gpu::Sampling sampling) { return std::string(gpu::samplingName(sampling)); }

void expectLevelsEqual(const CubeLevels& gpuLevels, const CubeLevels& cpuLevels, double tolerance, const std::string& what) {
    ASSERT_EQ(gpuLevels.size(), cpuLevels.size()) << what;
    for (std::size_t m = 0; m < cpuLevels.size(); ++m) {
        const double error = probetest::maxRelativeError(gpuLevels[m], cpuLevels[m]);
        ::testing::Test::RecordProperty(fmt::format("{} level {}", what, m), fmt::format("{:.3g}", error));
        EXPECT_LT(error, tolerance) << what << ", level " << m;
    }
}

} // namespace

TEST_F(GpuTest, FilterProbeIsOneRunOfAFilter) {
    const CubeImage source = probetest::randomProbe(16, 5);
    gpu::FilterSettings s;
    s.faceSize = 16;
    s.levelCount = 4;
    s.method.kind = MethodKind::fis;
    s.sampling = gpu::Sampling::exact;
    gpu::Filter filter(probetest::testDevice(), s);
    const CubeLevels expected = filter.run(source);
    const CubeLevels levels = gpu::filterProbe(probetest::testDevice(), s, source);
    ASSERT_EQ(levels.size(), expected.size());
    for (std::size_t m = 0; m < levels.size(); ++m) EXPECT_EQ(levels[m].rgb, expected[m].rgb) << "level " << m;
    s.faceSize = 12;
    EXPECT_THROW(gpu::filterProbe(probetest::testDevice(), s, source), ProbeError);
}

TEST_F(GpuTest, PyramidEqualsCpuModel) {
    const CubeImage source = probetest::randomProbe(32, 11);
    for (const probetest::SamplingCase& c : probetest::kSamplingCases)
        for (const PyramidSettings& pyramid : kAllPyramids) {
            gpu::Filter filter(probetest::testDevice(), settingsFor(MethodKind::fis, 32, 5, RoughnessMapping::gltf, pyramid, c.sampling));
            filter.run(source);
            expectLevelsEqual(filter.downloadPyramid(), buildPyramid(source, pyramid), c.tolerance,
                              describe(c.sampling) + " pyramid " + describe(pyramid));
        }
}

// On a device whose storage-buffer range holds fewer than a level's faces, exact sampling's pass 1
// writes each level through windows of whole faces (FilterPlan::pyramidWindows): the pyramid is the
// same. The test device, wrapped, with its range narrowed to two faces of level 0.
TEST_F(GpuTest, PyramidWrittenInWindowsEqualsCpuModel) {
    const CubeImage source = probetest::randomProbe(32, 11);
    const gpu::Device& shared = probetest::testDevice();
    const gpu::Device device(shared.instance(), shared.physicalDevice(), shared.device(), shared.queueFamily(), shared.queue());
    device.impl().limits.maxStorageBufferRange = uint32_t(2 * 34 * 34 * 16 + device.impl().limits.minStorageBufferOffsetAlignment);
    for (const PyramidSettings& pyramid : kAllPyramids) {
        gpu::Filter filter(device, settingsFor(MethodKind::fis, 32, 5, RoughnessMapping::gltf, pyramid, gpu::Sampling::exact));
        filter.run(source);
        int level0 = 0;
        for (const gpu::Dispatch& d : filter.dispatches()) level0 += d.pass == "pyramid" && d.level == 0 && d.groups > 1;
        EXPECT_EQ(level0, 3) << "level 0 in three windows of two faces";
        expectLevelsEqual(filter.downloadPyramid(), buildPyramid(source, pyramid), probetest::kSamplingCases[0].tolerance,
                          "pyramid in windows " + describe(pyramid));
    }
}

// Hardware sampling builds each mip above the tail in a dispatch of its own: mip 0 is the source's
// texels, each later one from the mip above through the sampler (its tolerance of the model from that
// mip); then the tail's mips in one dispatch from the 8x8 mip down, the first through the sampler too,
// each later one from the one before in shared memory with the exact path's arithmetic: the model's
// to float rounding.
TEST_F(GpuTest, PyramidMipsADispatchEachEqualCpuModel) {
    using Pass1 = std::vector<std::pair<int, int>>; // (first mip, mips) of each dispatch
    for (const int size : {32, 128, 256}) {
        const CubeImage source = probetest::randomProbe(size, 14);
        const int tailLevel = std::bit_width(unsigned(size / PROBE_PYRAMID_TAIL_SIZE)) - 1;
        Pass1 expected;
        for (int k = 0; k < tailLevel; ++k) expected.emplace_back(k, 1);
        expected.emplace_back(tailLevel, 4);
        for (const PyramidSettings& pyramid : kAllPyramids) {
            const std::string what = fmt::format("{}^2 {}", size, describe(pyramid));
            gpu::Filter filter(probetest::testDevice(), settingsFor(MethodKind::fis, size, defaultLevelCount(size), RoughnessMapping::gltf,
                                                                    pyramid, gpu::Sampling::hardware));
            filter.run(source);
            Pass1 pass1;
            for (const gpu::Dispatch& d : filter.dispatches())
                if (d.pass == "pyramid") pass1.emplace_back(d.level, d.levels);
            EXPECT_EQ(pass1, expected) << what;
            const CubeLevels gpuLevels = filter.downloadPyramid();
            expectLevelsEqual({gpuLevels[0]}, {source}, 1e-5, "mip 0, " + what);
            for (std::size_t k = 1; k < gpuLevels.size(); ++k)
                expectLevelsEqual({gpuLevels[k]}, {buildPyramid(gpuLevels[k - 1], pyramid)[1]},
                                  int(k) <= tailLevel ? probetest::kSamplingCases[1].tolerance : 1e-5,
                                  fmt::format("mip {} from mip {}, {}", k, k - 1, what));
        }
    }
}

// The tail's workgroup is 256 lanes where the device allows, else its limit (Vulkan guarantees 128
// invocations): a device at that limit builds the same pyramid, each loop taking more strides.
TEST_F(GpuTest, PyramidTailAtTheSmallestWorkgroupLimitEqualsTheDefault) {
    const gpu::Device& shared = probetest::testDevice();
    const gpu::Device device(shared.instance(), shared.physicalDevice(), shared.device(), shared.queueFamily(), shared.queue());
    if (shared.impl().limits.maxComputeWorkGroupInvocations < 256) GTEST_SKIP() << "the test device itself has fewer than 256 lanes";
    device.impl().limits.maxComputeWorkGroupInvocations = 128;
    const CubeImage source = probetest::randomProbe(64, 13);
    for (const PyramidSettings& pyramid : kAllPyramids) {
        const gpu::FilterSettings s = settingsFor(MethodKind::fis, 64, 6, RoughnessMapping::gltf, pyramid, gpu::Sampling::hardware);
        gpu::Filter wide(shared, s), narrow(device, s);
        wide.run(source);
        narrow.run(source);
        const CubeLevels expected = wide.downloadPyramid(), got = narrow.downloadPyramid();
        ASSERT_EQ(got.size(), expected.size());
        for (std::size_t k = 0; k < got.size(); ++k) EXPECT_EQ(got[k].rgb, expected[k].rgb) << describe(pyramid) << ", mip " << k;
    }
}

TEST_F(GpuTest, ConstantProbeStaysConstantInEveryPyramidLevel) {
    const glm::vec3 radiance(0.25f, 1.0f, 3.0f);
    for (const probetest::SamplingCase& c : probetest::kSamplingCases)
        for (const PyramidSettings& pyramid : kAllPyramids) {
            gpu::Filter filter(probetest::testDevice(), settingsFor(MethodKind::fis, 64, 6, RoughnessMapping::gltf, pyramid, c.sampling));
            filter.run(constantProbe(64, radiance));
            const CubeLevels levels = filter.downloadPyramid();
            ASSERT_EQ(levels.size(), 7u);
            for (const CubeImage& level : levels)
                EXPECT_LT(probetest::maxRelativeError(level, CubeImage(level.size, radiance)), 1e-6)
                    << describe(c.sampling) << " " << describe(pyramid) << ", size " << level.size;
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
    for (const probetest::SamplingCase& sampling : probetest::kSamplingCases) {
        unsigned seed = 20;
        for (const Case& c : cases) {
            const int levels = defaultLevelCount(c.size);
            const TapTable table = randomTable(c.size, levels, 8, c.form, c.mapping, c.pyramid, seed++);
            const CubeImage source = probetest::randomProbe(c.size, seed++);
            gpu::Filter filter(probetest::testDevice(), probetest::tableSettings(table, sampling.sampling));
            expectLevelsEqual(filter.run(source), tableFilter(source, table), sampling.tolerance,
                              fmt::format("{} table {} {}^2 {}", describe(sampling.sampling), tableFormName(c.form), c.size,
                                          roughnessMappingName(c.mapping)));
        }
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
    for (const probetest::SamplingCase& c : probetest::kSamplingCases) {
        gpu::Filter filter(probetest::testDevice(), probetest::tableSettings(table, c.sampling));
        expectLevelsEqual(filter.run(source), tableFilter(source, table), c.tolerance, describe(c.sampling) + " padded table");
    }
}

// A table that hands levels to FIS (TableLevel::fisSamples): those levels run FIS's pass on the
// table's pyramid, equal to FIS at that count and bias 0; the others stay the table's.
TEST_F(GpuTest, TableHandOffEqualsFisAtThoseLevels) {
    const PyramidSettings pyramid = kAllPyramids[0];
    TapTable table = randomTable(32, 5, 8, TableForm::quadratic, RoughnessMapping::gltf, pyramid, 25);
    table.levels[1].fisSamples = 24;
    table.levels[3].fisSamples = 7;
    const CubeImage source = probetest::randomProbe(32, 26);
    FisSettings fis;
    fis.levelSamples = {1, 24, 1, 7, 1};
    fis.pyramid = pyramid;
    const CubeLevels asFis = filterWithTaps(buildPyramid(source, pyramid), 5, fisTapGenerator(32, 5, RoughnessMapping::gltf, fis));
    const CubeLevels asTable = tableFilter(source, table);
    for (const probetest::SamplingCase& c : probetest::kSamplingCases) {
        gpu::Filter filter(probetest::testDevice(), probetest::tableSettings(table, c.sampling));
        const CubeLevels levels = filter.run(source);
        for (int m = 1; m < 5; ++m) {
            const CubeImage& expected = table.levels[m].fisSamples > 0 ? asFis[m] : asTable[m];
            EXPECT_LT(probetest::maxRelativeError(levels[m], expected), c.tolerance) << describe(c.sampling) << " level " << m;
        }
        EXPECT_GT(probetest::maxRelativeError(levels[1], asTable[1]), 10 * c.tolerance) << "level 1 is not the table's";
        std::vector<std::string> passes;
        for (const gpu::Dispatch& d : filter.dispatches())
            if (d.pass != "pyramid") passes.push_back(d.pass);
        EXPECT_EQ(passes, (std::vector<std::string>{"table", "fis", "table", "fis", "table"})) << describe(c.sampling);
    }
    // The CPU model of the method is the same.
    const CubeLevels model = filterOnCpu(source, 5, RoughnessMapping::gltf, probetest::tableSettings(table, gpu::Sampling::exact).method);
    for (int m = 1; m < 5; ++m)
        EXPECT_LT(probetest::maxRelativeError(model[m], table.levels[m].fisSamples > 0 ? asFis[m] : asTable[m]), 1e-6) << "level " << m;
}

TEST_F(GpuTest, FisEqualsCpuModel) {
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
    for (const probetest::SamplingCase& sampling : probetest::kSamplingCases)
        for (const Case& c : cases) {
            gpu::FilterSettings s = settingsFor(MethodKind::fis, 32, 5, c.mapping, c.pyramid, sampling.sampling);
            s.method.fis.samples = c.samples;
            s.method.fis.bias = c.bias;
            gpu::Filter filter(probetest::testDevice(), s);
            expectLevelsEqual(
                filter.run(source), filterOnCpu(source, 5, c.mapping, s.method), sampling.tolerance,
                fmt::format("{} fis {} bias {} {}", describe(sampling.sampling), c.samples, c.bias, roughnessMappingName(c.mapping)));
        }
}

// FIS with the Charlie lobe: the same shader with the host's Charlie samples, every level filtered
// (level 0 too: no Charlie level is a copy).
TEST_F(GpuTest, CharlieFisEqualsCpuModel) {
    const CubeImage source = probetest::randomProbe(32, 32);
    for (const probetest::SamplingCase& sampling : probetest::kSamplingCases) {
        gpu::FilterSettings s = settingsFor(MethodKind::fis, 32, 5, RoughnessMapping::gltf, kAllPyramids[0], sampling.sampling);
        s.method.fis.samples = 64;
        s.method.lobe = Lobe::charlie;
        gpu::Filter filter(probetest::testDevice(), s);
        const CubeLevels levels = filter.run(source);
        expectLevelsEqual(levels, filterOnCpu(source, 5, RoughnessMapping::gltf, s.method), sampling.tolerance,
                          describe(sampling.sampling) + " charlie fis");
        EXPECT_GT(probetest::maxRelativeError(levels[0], source), 0.1) << "level 0 is filtered, not copied";
    }
}

// Per-level sample counts (the sweep's FIS mixes): each level as FIS with that level's count.
TEST_F(GpuTest, FisPerLevelEqualsCpuModel) {
    const CubeImage source = probetest::randomProbe(32, 31);
    gpu::FilterSettings s = settingsFor(MethodKind::fis, 32, 5, RoughnessMapping::gltf, kAllPyramids[0], gpu::Sampling::exact);
    s.method.fis.samples = 8;
    s.method.fis.levelSamples = {1, 8, 3, 64, 256};
    gpu::Filter filter(probetest::testDevice(), s);
    const CubeLevels levels = filter.run(source);
    for (int m = 1; m < 5; ++m) {
        FilterMethod uniform = s.method;
        uniform.fis.samples = s.method.fis.levelSamples[m];
        uniform.fis.levelSamples.clear();
        expectLevelsEqual({levels[m]}, {filterOnCpu(source, 5, RoughnessMapping::gltf, uniform)[m]}, 1e-5,
                          fmt::format("fis level {} with {} samples", m, uniform.fis.samples));
    }
    s.method.fis.levelSamples = {8, 8, 8};
    EXPECT_THROW(gpu::Filter(probetest::testDevice(), s), ParameterError);
    s.method.fis.levelSamples = {8, 8, 0, 8, 8};
    EXPECT_THROW(gpu::Filter(probetest::testDevice(), s), ParameterError);
}

// FIS on a dual-paraboloid map: the map and the samples' levels on it as the CPU model makes them,
// uniform and per-level counts, every output format's shader from the same source; a constant stays
// constant; hardware sampling is refused (the map is read from a buffer).
TEST_F(GpuTest, ParaboloidFisEqualsCpuModel) {
    const CubeImage source = probetest::randomProbe(32, 33);
    for (const double bias : {0.0, 1.0}) {
        gpu::FilterSettings s = settingsFor(MethodKind::fis, 32, 5, RoughnessMapping::gltf, kAllPyramids[0], gpu::Sampling::automatic);
        s.method.fis.map = FisMap::paraboloid;
        s.method.fis.samples = 24;
        s.method.fis.bias = bias;
        if (bias > 0.0) s.method.fis.levelSamples = {8, 8, 32, 128, 512};
        gpu::Filter filter(probetest::testDevice(), s);
        EXPECT_EQ(filter.sampling(), gpu::Sampling::exact);
        expectLevelsEqual(filter.run(source), filterOnCpu(source, 5, RoughnessMapping::gltf, s.method), 1e-5,
                          fmt::format("paraboloid fis bias {}", bias));
    }
    gpu::FilterSettings s = settingsFor(MethodKind::fis, 32, 5, RoughnessMapping::gltf, kAllPyramids[0], gpu::Sampling::exact);
    s.method.fis.map = FisMap::paraboloid;
    const glm::vec3 radiance(0.25f, 1.0f, 3.0f);
    gpu::Filter filter(probetest::testDevice(), s);
    const CubeLevels levels = filter.run(constantProbe(32, radiance));
    for (int m = 0; m < 5; ++m)
        EXPECT_LT(probetest::maxRelativeError(levels[m], CubeImage(32 >> m, radiance)), 1e-5) << "paraboloid white furnace, level " << m;
    s.sampling = gpu::Sampling::hardware;
    EXPECT_THROW(gpu::Filter(probetest::testDevice(), s), ParameterError);
}

// A map larger than the device's storage-buffer range is written in windows (FilterPlan::paraboloidWindows),
// each level's after the level above, as at 2048^2 where its level 0 takes 512 MiB: the same bits as
// a map written level by level.
TEST_F(GpuTest, ParaboloidMapWrittenInWindowsEqualsOneWindowALevel) {
    const gpu::Device& shared = probetest::testDevice();
    const gpu::Device device(shared.instance(), shared.physicalDevice(), shared.device(), shared.queueFamily(), shared.queue());
    // 3000 texels a window: the bordered 32^2 source (6 faces of 34^2) in three windows of two faces,
    // the map's level 0 (two 64^2 images) in three, its level 1 (two 32^2) in one.
    device.impl().limits.maxStorageBufferRange = 3000 * 16;
    device.impl().limits.minStorageBufferOffsetAlignment = 16;
    gpu::FilterSettings s = settingsFor(MethodKind::fis, 32, 5, RoughnessMapping::gltf, kAllPyramids[0], gpu::Sampling::exact);
    s.method.fis.map = FisMap::paraboloid;
    const CubeImage source = probetest::randomProbe(32, 34);
    gpu::Filter whole(shared, s), windowed(device, s);
    const CubeLevels expected = whole.run(source), levels = windowed.run(source);
    const auto pyramidDispatches = [](const gpu::Filter& f, int level) {
        return std::count_if(f.dispatches().begin(), f.dispatches().end(),
                             [&](const gpu::Dispatch& d) { return d.pass == "pyramid" && d.level == level; });
    };
    for (int m = 0; m < 5; ++m) EXPECT_EQ(levels[m].rgb, expected[m].rgb) << "level " << m;
    // Level 0: the bordered source (with its corners) per window, then the map's level 0.
    EXPECT_EQ(pyramidDispatches(whole, 0), 1 + 1);
    EXPECT_EQ(pyramidDispatches(windowed, 0), 3 + 3);
    EXPECT_EQ(pyramidDispatches(windowed, 1), 1);
}

// Pass 2's filtered levels in one dispatch where the device offers a storage image for each (lavapipe
// does), in groups of four where it offers the four every device does: the same bits in both sampling
// modes, for the table and FIS, and a dispatch fewer at 64^2 (GGX: level 0 copied, levels
// 1-6 in one, not 1-4 and 5-6; Charlie, which copies none: levels 0-6 in one, not 0-3 and 4-6).
TEST_F(GpuTest, LevelsInOneDispatchEqualGroupsOfFour) {
    const gpu::Device& shared = probetest::testDevice();
    ASSERT_GE(shared.impl().limits.maxPerStageDescriptorStorageImages, gpu::kWideWrittenMipCount)
        << "the test device's own groups are wide";
    const gpu::Device narrow(shared.instance(), shared.physicalDevice(), shared.device(), shared.queueFamily(), shared.queue());
    narrow.impl().limits.maxPerStageDescriptorStorageImages = 4;
    const TapTable table = randomTable(64, 7, 8, TableForm::quadratic, RoughnessMapping::gltf, kAllPyramids[0], 41);
    const CubeImage source = probetest::randomProbe(64, 42);
    using Groups = std::vector<std::pair<int, int>>; // (first level, levels) of each dispatch
    struct Case {
        MethodKind method;
        Lobe lobe;
        Groups wide, four;
    };
    const Case cases[] = {{MethodKind::table, Lobe::ggx, {{0, 1}, {1, 6}}, {{0, 1}, {1, 4}, {5, 2}}},
                          {MethodKind::fis, Lobe::ggx, {{0, 1}, {1, 6}}, {{0, 1}, {1, 4}, {5, 2}}},
                          {MethodKind::fis, Lobe::charlie, {{0, 7}}, {{0, 4}, {4, 3}}}};
    for (const probetest::SamplingCase& c : probetest::kSamplingCases)
        for (const Case& k : cases) {
            gpu::FilterSettings s = settingsFor(k.method, 64, 7, RoughnessMapping::gltf, kAllPyramids[0], c.sampling);
            s.method.table = &table;
            s.method.lobe = k.lobe;
            gpu::Filter wide(shared, s), four(narrow, s);
            const CubeLevels expected = four.run(source), levels = wide.run(source);
            const std::string what = fmt::format("{} {} {}", describe(c.sampling), methodKindName(k.method), lobeName(k.lobe));
            for (int m = 0; m < 7; ++m) EXPECT_EQ(levels[m].rgb, expected[m].rgb) << what << ", level " << m;
            const auto groups = [&](const gpu::Filter& f) {
                Groups g;
                for (const gpu::Dispatch& d : f.dispatches())
                    if (d.pass == methodKindName(k.method)) g.emplace_back(d.level, d.levels);
                return g;
            };
            EXPECT_EQ(groups(wide), k.wide) << what;
            EXPECT_EQ(groups(four), k.four) << what;
            EXPECT_EQ(wide.dispatches().size() + 1, four.dispatches().size()) << what;
        }
}

TEST_F(GpuTest, WhiteFurnaceEveryMethod) {
    const glm::vec3 radiance(0.25f, 1.0f, 3.0f);
    const CubeImage constant = constantProbe(32, radiance);
    const TapTable table = randomTable(32, 5, 8, TableForm::quadratic, RoughnessMapping::gltf, kAllPyramids[0], 40);
    for (const probetest::SamplingCase& c : probetest::kSamplingCases)
        for (MethodKind method : {MethodKind::table, MethodKind::fis, MethodKind::reference}) {
            gpu::FilterSettings s = settingsFor(method, 32, 5, RoughnessMapping::gltf, kAllPyramids[0], c.sampling);
            s.method.table = &table;
            gpu::Filter filter(probetest::testDevice(), s);
            const CubeLevels levels = filter.run(constant);
            for (int m = 0; m < 5; ++m)
                EXPECT_LT(probetest::maxRelativeError(levels[m], CubeImage(32 >> m, radiance)), 1e-5)
                    << describe(c.sampling) << " " << methodKindName(method) << ", level " << m;
        }
}

// FIS with 1024 samples and bias 0 over the B-spline pyramid is within 3% image L1 of the
// reference at every filtered level of a smooth sky.
TEST_F(GpuTest, Fis1024NearReferenceOnSky) {
    const int size = 64, levels = defaultLevelCount(size);
    const CubeImage sky = skyProbe(size);
    gpu::FilterSettings s = settingsFor(MethodKind::fis, size, levels, RoughnessMapping::gltf, kAllPyramids[0], gpu::Sampling::exact);
    s.method.fis.samples = 1024;
    gpu::Filter filter(probetest::testDevice(), s);
    const CubeLevels fis = filter.run(sky);
    const CubeLevels reference = referenceFilter(sky, levels, RoughnessMapping::gltf);
    for (int m = 1; m < levels; ++m) {
        const double error = imageL1(fis[m], reference[m]);
        ::testing::Test::RecordProperty(fmt::format("level{}_image_l1", m), fmt::format("{:.4f}", error));
        EXPECT_LT(error, 0.03) << "level " << m;
    }
}

// The exact table shader takes a texel's third frame per subgroup (subgroupAny): on a device without
// subgroup vote in compute shaders exact sampling of a table is refused, naming the device; hardware
// sampling, which needs no subgroup operation, and FIS still run.
TEST_F(GpuTest, TableMethodNeedsSubgroupVote) {
    const gpu::Device& shared = probetest::testDevice();
    const gpu::Device device(shared.instance(), shared.physicalDevice(), shared.device(), shared.queueFamily(), shared.queue());
    device.impl().computeSubgroupVote = false; // what a device without it reports
    const TapTable table = randomTable(16, 4, 4, TableForm::quadratic, RoughnessMapping::gltf, kAllPyramids[0], 50);
    gpu::FilterSettings s = probetest::tableSettings(table, gpu::Sampling::exact);
    try {
        gpu::Filter filter(device, s);
        ADD_FAILURE() << "the table method was not refused";
    } catch (const ProbeError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("subgroup vote"), std::string::npos) << message;
        EXPECT_NE(message.find(device.info().name), std::string::npos) << message;
    }
    s.sampling = gpu::Sampling::hardware;
    EXPECT_NO_THROW(gpu::Filter(device, s));
    s.sampling = gpu::Sampling::exact;
    s.method.kind = MethodKind::fis;
    EXPECT_NO_THROW(gpu::Filter(device, s));
}

// Finite input gives finite output (probe/range_scale.h), on the GPU and in the CPU model alike: a
// probe all at FLT_MAX stays FLT_MAX at every level, one texel at FLT_MAX among ordinary ones gives
// the model's levels, and a 16-bit output saturates at 65504.
TEST_F(GpuTest, LargestFiniteValuesEveryMethod) {
    constexpr float largest = std::numeric_limits<float>::max();
    const CubeImage allLargest(16, glm::vec3(largest));
    CubeImage oneLargest = probetest::randomProbe(16, 50);
    oneLargest.rgb[3 * 700 + 1] = largest;
    const TapTable table = randomTable(16, 4, 8, TableForm::quadratic, RoughnessMapping::authors, kAllPyramids[0], 51);
    auto expectFinite = [](const CubeLevels& levels, float limit, const std::string& what) {
        for (std::size_t m = 0; m < levels.size(); ++m)
            for (float v : levels[m].rgb) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= limit) << what << ", level " << m << ": " << v;
    };
    for (const probetest::SamplingCase& c : probetest::kSamplingCases)
        for (MethodKind method : {MethodKind::table, MethodKind::fis, MethodKind::reference}) {
            gpu::FilterSettings s = settingsFor(method, 16, 4, RoughnessMapping::authors, kAllPyramids[0], c.sampling);
            s.method.table = &table;
            const std::string what = fmt::format("{} {}", describe(c.sampling), methodKindName(method));
            gpu::Filter filter(probetest::testDevice(), s);
            const CubeLevels gpuAll = filter.run(allLargest), cpuAll = filterOnCpu(allLargest, 4, s.mapping, s.method);
            expectFinite(gpuAll, largest, what + " all FLT_MAX");
            expectFinite(cpuAll, largest, what + " all FLT_MAX, CPU model");
            for (int m = 0; m < 4; ++m) {
                EXPECT_LT(probetest::maxRelativeError(gpuAll[m], CubeImage(16 >> m, glm::vec3(largest))), 1e-5) << what << ", level " << m;
                EXPECT_LT(probetest::maxRelativeError(cpuAll[m], CubeImage(16 >> m, glm::vec3(largest))), 1e-5) << what << ", level " << m;
            }
            const CubeLevels gpuOne = filter.run(oneLargest);
            expectFinite(gpuOne, largest, what + " one FLT_MAX");
            // Relative to the brightest texel a read blends, as the other comparisons: here the spike.
            const CubeLevels cpuOne = filterOnCpu(oneLargest, 4, s.mapping, s.method);
            for (int m = 0; m < 4; ++m) {
                const float brightest = *std::max_element(cpuOne[m].rgb.begin(), cpuOne[m].rgb.end());
                EXPECT_LT(probetest::maxRelativeError(gpuOne[m], cpuOne[m], brightest), c.tolerance) << what << ", level " << m;
            }

            s.outputFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
            gpu::Filter half(probetest::testDevice(), s);
            expectFinite(half.run(allLargest), 65504.0f, what + " all FLT_MAX, rgba16f");
            expectFinite(half.run(oneLargest), 65504.0f, what + " one FLT_MAX, rgba16f");
        }
}

// A dispatch of more than 65535 workgroups goes over y (ComputePipeline::dispatch): level 0 of a
// 1024^2 probe, 6.3M texels, is copied whole, its last face included.
TEST_F(GpuTest, LargeDispatchCoversEveryTexel) {
    const CubeImage source = probetest::randomProbe(1024, 5);
    gpu::FilterSettings s = settingsFor(MethodKind::fis, 1024, 1, RoughnessMapping::gltf, {}, gpu::Sampling::hardware);
    gpu::Filter filter(probetest::testDevice(), s);
    const CubeLevels levels = filter.run(source);
    std::size_t differing = 0, first = 0;
    for (std::size_t t = 0; t < texelCount(1024); ++t)
        if (levels[0].texel(t) != source.texel(t) && differing++ == 0) first = t;
    EXPECT_EQ(differing, 0u) << "first at texel " << first;
}
