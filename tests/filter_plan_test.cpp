// What a Filter computes and allocates for its settings on a device (runtime/src/filter_plan.h),
// planned without a device from capabilities set by hand: the same function that the Filter and
// Filter::checkLimits follow.
#include <gtest/gtest.h>

#include "buffer.h"
#include "filter_plan.h"
#include "probe/error.h"
#include "probe/tap_table.h"

namespace {

using namespace probe;
using namespace probe::gpu;

constexpr VkFormatFeatureFlags kEverything = VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT |
                                             VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT | VK_FORMAT_FEATURE_TRANSFER_SRC_BIT |
                                             VK_FORMAT_FEATURE_TRANSFER_DST_BIT;

// A GPU with every feature the runtime asks for and Vulkan's least buffer range (128 MiB).
DeviceCapabilities gpu() {
    DeviceCapabilities d;
    d.name = "test GPU";
    d.maxStorageBufferRange = 1u << 27;
    d.maxTexelBufferElements = 1u << 27;
    for (VkFormat f : {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_B10G11R11_UFLOAT_PACK32, VK_FORMAT_R32_UINT})
        d.formatFeatures[f] = kEverything;
    // What Vulkan requires of E5B9G9R9, and what GPUs offer: no storage.
    d.formatFeatures[VK_FORMAT_E5B9G9R9_UFLOAT_PACK32] =
        VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
    return d;
}

FilterSettings fisSettings(int size, Lobe lobe = Lobe::ggx) {
    FilterSettings s;
    s.method.kind = MethodKind::fis;
    s.method.lobe = lobe;
    s.faceSize = size;
    s.levelCount = defaultLevelCount(size);
    return s;
}

TEST(FilterPlan, GgxLevelZeroIsACopyAndCharlieHasNone) {
    const FilterPlan ggx = planFilter(fisSettings(128), gpu());
    EXPECT_EQ(ggx.copyLevels, 1u);
    EXPECT_TRUE(ggx.isCopy(0));
    EXPECT_FALSE(ggx.isCopy(1));
    EXPECT_EQ(ggx.computedLevels, (std::vector<int>{0, 1, 2, 3, 4, 5, 6}));
    EXPECT_TRUE(ggx.filters && ggx.buildsPyramid);
    EXPECT_EQ(ggx.pyramidLevels, 8);
    EXPECT_EQ(ggx.pyramidDepth, 7);
    EXPECT_EQ(ggx.outputOffsets.size(), 8u);
    EXPECT_EQ(ggx.outputOffsets.back(), uint32_t(6 * (128 * 128 + 64 * 64 + 32 * 32 + 16 * 16 + 8 * 8 + 4 * 4 + 2 * 2)));
    EXPECT_EQ(planFilter(fisSettings(128, Lobe::charlie), gpu()).copyLevels, 0u);

    // Level 0 alone is a copy: no pyramid.
    FilterSettings s = fisSettings(128);
    s.computedLevels = {0};
    const FilterPlan copy = planFilter(s, gpu());
    EXPECT_FALSE(copy.filters || copy.buildsPyramid);
}

// Pass 2 writes consecutive levels of one pass in one dispatch, up to the four storage images a
// dispatch may write; copies, the reference's levels and a table's hand-offs to FIS go apart.
TEST(FilterPlan, LevelGroupsShareADispatch) {
    using Groups = std::vector<std::vector<int>>;
    EXPECT_EQ(planFilter(fisSettings(128), gpu()).levelGroups, (Groups{{0}, {1, 2, 3, 4}, {5, 6}}));
    EXPECT_EQ(planFilter(fisSettings(128, Lobe::charlie), gpu()).levelGroups, (Groups{{0, 1, 2, 3}, {4, 5, 6}}));
    FilterSettings some = fisSettings(128);
    some.computedLevels = {1, 2, 4, 5, 6};
    EXPECT_EQ(planFilter(some, gpu()).levelGroups, (Groups{{1, 2}, {4, 5, 6}}));
    FilterSettings reference = fisSettings(32);
    reference.method.kind = MethodKind::reference;
    EXPECT_EQ(planFilter(reference, gpu()).levelGroups, (Groups{{0}, {1}, {2}, {3}, {4}}));

    TapTable table = emptyTable(32, 6, 4, TableForm::constant, RoughnessMapping::gltf, {});
    for (TableLevel& level : table.levels) level.coefficients.assign(level.coefficients.size(), 0.0);
    table.levels[2].fisSamples = 16;
    FilterSettings handOff;
    handOff.method = {MethodKind::table, &table, {}};
    handOff.faceSize = 32;
    handOff.levelCount = 6;
    const FilterPlan plan = planFilter(handOff, gpu());
    EXPECT_EQ(plan.fisLevels, 1u << 2);
    EXPECT_EQ(plan.levelGroups, (Groups{{0}, {1}, {2}, {3, 4, 5}}));

    // A device with the storage images of every level: the filtered levels in one dispatch, a
    // Charlie lobe's from level 0 at the largest size; the copy, a level handed to FIS and the
    // reference's levels still apart.
    EXPECT_EQ(planFilter(fisSettings(128), gpu()).writtenMipCount, kWrittenMipCount);
    DeviceCapabilities wide = gpu();
    wide.maxPerStageDescriptorStorageImages = kWideWrittenMipCount;
    EXPECT_EQ(planFilter(fisSettings(128), wide).writtenMipCount, kWideWrittenMipCount);
    EXPECT_EQ(planFilter(fisSettings(128), wide).levelGroups, (Groups{{0}, {1, 2, 3, 4, 5, 6}}));
    FilterSettings everyLevel = fisSettings(2048, Lobe::charlie);
    everyLevel.levelCount = 12;
    EXPECT_EQ(planFilter(everyLevel, wide).levelGroups, (Groups{{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}}));
    EXPECT_EQ(planFilter(handOff, wide).levelGroups, (Groups{{0}, {1}, {2}, {3, 4, 5}}));
    EXPECT_EQ(planFilter(reference, wide).levelGroups, (Groups{{0}, {1}, {2}, {3}, {4}}));
    wide.maxPerStageDescriptorStorageImages = kWideWrittenMipCount - 1;
    EXPECT_EQ(planFilter(fisSettings(128), wide).levelGroups, (Groups{{0}, {1, 2, 3, 4}, {5, 6}}));
}

TEST(FilterPlan, SamplingByDeviceAndMethod) {
    DeviceCapabilities cpu = gpu();
    cpu.cpu = true;
    const FilterPlan onGpu = planFilter(fisSettings(64), gpu());
    EXPECT_EQ(onGpu.sampling, Sampling::hardware);
    EXPECT_EQ(onGpu.pyramidFormat, VK_FORMAT_R16G16B16A16_SFLOAT); // the format engines filter in
    EXPECT_EQ(onGpu.pyramidTailLevel, 3);                          // the 8^2 level of a 64^2 pyramid
    // Pass 1's tail starts at the 8^2 mip at every size; a depth above it leaves none.
    EXPECT_EQ(planFilter(fisSettings(32), gpu()).pyramidTailLevel, 2);
    EXPECT_EQ(planFilter(fisSettings(16), gpu()).pyramidTailLevel, 1);
    EXPECT_EQ(planFilter(fisSettings(2048), gpu()).pyramidTailLevel, 8);
    FilterSettings shallow = fisSettings(2048);
    shallow.pyramidDepth = 5;
    EXPECT_EQ(planFilter(shallow, gpu()).pyramidTailLevel, 0);
    EXPECT_EQ(onGpu.pyramidTexels, 1u);                                    // the pyramid is an image
    EXPECT_EQ(planFilter(fisSettings(64), cpu).sampling, Sampling::exact); // a CPU device reads exactly
    EXPECT_GT(planFilter(fisSettings(64), cpu).pyramidTexels, 1u);         // into a bordered buffer

    // Without RGBA16F filtering, the RGBA32F pyramid.
    DeviceCapabilities noHalf = gpu();
    noHalf.formatFeatures[VK_FORMAT_R16G16B16A16_SFLOAT] = VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT;
    EXPECT_EQ(planFilter(fisSettings(64), noHalf).pyramidFormat, VK_FORMAT_R32G32B32A32_SFLOAT);

    // An E5B9G9R9 pyramid where asked for: filtered as itself, stored as R32_UINT bits, which it needs.
    FilterSettings sharedExponent = fisSettings(64);
    sharedExponent.pyramidFormat = VK_FORMAT_E5B9G9R9_UFLOAT_PACK32;
    EXPECT_EQ(planFilter(sharedExponent, gpu()).pyramidFormat, VK_FORMAT_E5B9G9R9_UFLOAT_PACK32);
    DeviceCapabilities noUintStorage = gpu();
    noUintStorage.formatFeatures[VK_FORMAT_R32_UINT] = VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT;
    EXPECT_THROW(planFilter(sharedExponent, noUintStorage), ProbeError);

    // The reference reads every texel exactly and sums into the accumulator; no pyramid is built.
    FilterSettings reference = fisSettings(32);
    reference.method.kind = MethodKind::reference;
    const FilterPlan r = planFilter(reference, gpu());
    EXPECT_EQ(r.sampling, Sampling::exact);
    EXPECT_FALSE(r.buildsPyramid);
    EXPECT_EQ(r.accumulatorTexels, r.outputOffsets.back());

    // FIS on the dual-paraboloid map reads the source alone; hardware sampling is refused there.
    FilterSettings paraboloid = fisSettings(32);
    paraboloid.method.fis.map = FisMap::paraboloid;
    const FilterPlan p = planFilter(paraboloid, gpu());
    EXPECT_TRUE(p.paraboloid);
    EXPECT_EQ(p.pyramidDepth, 0);
    EXPECT_EQ(p.sampling, Sampling::exact);
    paraboloid.sampling = Sampling::hardware;
    EXPECT_THROW(planFilter(paraboloid, gpu()), ParameterError);
}

TEST(FilterPlan, OutputFormatsThroughTheConversionWhereStorageIsMissing) {
    FilterSettings s = fisSettings(16);
    s.outputFormat = VK_FORMAT_B10G11R11_UFLOAT_PACK32;
    EXPECT_FALSE(planFilter(s, gpu()).convertOutput);
    DeviceCapabilities noStorage = gpu();
    noStorage.formatFeatures[VK_FORMAT_B10G11R11_UFLOAT_PACK32] = VK_FORMAT_FEATURE_TRANSFER_DST_BIT;
    EXPECT_TRUE(planFilter(s, noStorage).convertOutput);
    noStorage.formatFeatures[VK_FORMAT_R32_UINT] = 0;
    EXPECT_THROW(planFilter(s, noStorage), ProbeError);
    s.outputFormat = VK_FORMAT_R8G8B8A8_UNORM;
    EXPECT_THROW(planFilter(s, gpu()), ParameterError);
}

TEST(FilterPlan, PyramidWindowsCoverEachLevelWithinTheStorageRange) {
    // Exact sampling at 2048^2: a 513.5 MiB pyramid buffer, read as a texel buffer and written through
    // windows of at most 128 MiB, their offsets aligned as the device asks.
    FilterSettings s = fisSettings(2048);
    s.sampling = Sampling::exact;
    DeviceCapabilities d = gpu();
    d.minStorageBufferOffsetAlignment = 256;
    const FilterPlan plan = planFilter(s, d);
    EXPECT_EQ(plan.pyramidTexels, plan.pyramidOffsets.back());
    EXPECT_GT(plan.pyramidTexels * 16, std::size_t(4) << 27);
    int level = -1, face = 0;
    std::vector<int> windowsOf(std::size_t(plan.pyramidLevels), 0);
    for (const PyramidWindow& w : plan.pyramidWindows) {
        if (w.level != level) { // a new level starts at face 0, after the last one ended at face 6
            EXPECT_EQ(face, level < 0 ? 0 : kFaceCount);
            EXPECT_EQ(w.level, level + 1);
            level = w.level;
            face = 0;
        }
        EXPECT_EQ(w.firstFace, face);
        EXPECT_GE(w.faceCount, 1);
        face += w.faceCount;
        ++windowsOf[std::size_t(w.level)];
        // Aligned, within the range, and holding the window's faces (the tail's: its levels' faces).
        const std::size_t perFace = pyramidLevelTexels(2048 >> w.level) / kFaceCount;
        const std::size_t start = plan.pyramidOffsets[std::size_t(w.level)] + std::size_t(w.firstFace) * perFace;
        const bool tail = w.level == plan.pyramidTailLevel;
        EXPECT_EQ(w.first * 16 % 256, 0u);
        EXPECT_LE(w.first, start);
        EXPECT_EQ(w.first + w.texels, tail ? plan.pyramidOffsets.back() : start + std::size_t(w.faceCount) * perFace);
        EXPECT_LE(w.texels * 16, std::size_t(1) << 27);
    }
    EXPECT_EQ(plan.pyramidTailLevel, 8); // 8^2: the tail writes levels 8 to 11 through one window
    EXPECT_EQ(level, plan.pyramidTailLevel);
    EXPECT_EQ(face, kFaceCount);
    EXPECT_EQ(windowsOf[0], 6); // a 2050^2 face takes 64.1 MiB: one a window
    EXPECT_EQ(windowsOf[1], 1); // the whole level takes 96.5 MiB
    // 128^2 and the reference: one window per level written, the tail's for levels 4 to 7.
    EXPECT_EQ(planFilter(fisSettings(128), d).pyramidWindows.size(), 0u); // FIS reads a cube image where it can
    FilterSettings exact128 = fisSettings(128);
    exact128.sampling = Sampling::exact;
    EXPECT_EQ(planFilter(exact128, d).pyramidWindows.size(), 5u);
    exact128.pyramidDepth = 3; // no level from the tail's on
    EXPECT_EQ(planFilter(exact128, d).pyramidTailLevel, 0);
    EXPECT_EQ(planFilter(exact128, d).pyramidWindows.size(), 4u);
    FilterSettings reference = exact128;
    reference.method.kind = MethodKind::reference;
    ASSERT_EQ(planFilter(reference, d).pyramidWindows.size(), 1u);
    EXPECT_EQ(planFilter(reference, d).pyramidWindows[0].faceCount, kFaceCount);
}

TEST(FilterPlan, ParaboloidMapWindowsCoverEachLevelWithinTheStorageRange) {
    // FIS on the paraboloid map at 2048^2: the map (682.7 MiB, level 0 two 4096^2 images) follows the
    // bordered source in the pyramid buffer, written through windows of at most 128 MiB with aligned
    // offsets, read as one texel buffer of 70.0 million texels.
    FilterSettings s = fisSettings(2048);
    s.method.fis.map = FisMap::paraboloid;
    DeviceCapabilities d = gpu();
    d.minStorageBufferOffsetAlignment = 256;
    const FilterPlan plan = planFilter(s, d);
    ASSERT_TRUE(plan.paraboloid);
    EXPECT_EQ(plan.accumulatorTexels, 1u);
    std::size_t mapTexels = 0;
    for (int size = 4096; size >= 1; size /= 2) mapTexels += 2 * std::size_t(size) * std::size_t(size);
    EXPECT_EQ(plan.pyramidTexels, plan.pyramidOffsets[1] + mapTexels);
    EXPECT_EQ(plan.pyramidWindows.size(), 6u); // the bordered source, a face a window
    int level = -1;
    std::size_t next = 0, levelFirst = plan.pyramidOffsets[1], levelTexels = 0;
    std::vector<int> windowsOf(13, 0);
    for (const ParaboloidWindow& w : plan.paraboloidWindows) {
        if (w.level != level) { // a new level starts at its texel 0, after the last one ended
            EXPECT_EQ(next, levelTexels);
            EXPECT_EQ(w.level, level + 1);
            levelFirst += levelTexels;
            level = w.level;
            levelTexels = 2 * std::size_t(4096 >> level) * std::size_t(4096 >> level);
            next = 0;
        }
        EXPECT_EQ(w.start, next);
        EXPECT_GE(w.count, 1u);
        next += w.count;
        ++windowsOf[std::size_t(w.level)];
        EXPECT_EQ(w.first * 16 % 256, 0u);
        EXPECT_LE(w.first, levelFirst + w.start);
        EXPECT_EQ(w.first + w.texels, levelFirst + w.start + w.count);
        EXPECT_LE(w.texels * 16, std::size_t(1) << 27);
    }
    EXPECT_EQ(level, 12);
    EXPECT_EQ(next, 2u);
    EXPECT_EQ(windowsOf[0], 5); // 512 MiB in windows of 128 MiB, the first starting after an aligned offset
    EXPECT_EQ(windowsOf[1], 2); // 128 MiB, and a window is that less its offset's slack
    EXPECT_EQ(levelFirst + 2, plan.pyramidTexels);
}

TEST(FilterPlan, BatchPyramidHoldsEachLevelOfEveryCubeInTurn) {
    // 64 exact 128^2 probes: level 0 of all of them (384 faces of 130^2 texels, 98.9 MiB) in one
    // window, each level after the last one of every cube, the buffer 64 times one probe's; the
    // tail's window from its level to the buffer's end.
    FilterSettings s = fisSettings(128);
    s.sampling = Sampling::exact;
    const FilterPlan one = planFilter(s, gpu());
    s.batchSize = 64;
    DeviceCapabilities d = gpu();
    d.maxImageArrayLayers = 2048;
    const FilterPlan plan = planFilter(s, d);
    EXPECT_EQ(plan.pyramidTexels, 64 * one.pyramidTexels);
    ASSERT_EQ(plan.pyramidWindows.size(), one.pyramidWindows.size());
    for (const PyramidWindow& w : plan.pyramidWindows) {
        EXPECT_EQ(w.firstFace, 0);
        EXPECT_EQ(w.faceCount, 64 * kFaceCount);
        EXPECT_EQ(w.first, 64 * std::size_t(plan.pyramidOffsets[std::size_t(w.level)]));
        if (w.level == plan.pyramidTailLevel) EXPECT_EQ(w.first + w.texels, plan.pyramidTexels);
        else EXPECT_EQ(w.texels, pyramidLevelTexels(128 >> w.level) * 64);
    }
    // A range of 100 faces at level 0: four windows of whole faces across the cubes.
    d.maxStorageBufferRange = 100 * 130 * 130 * 16;
    const FilterPlan narrow = planFilter(s, d);
    std::vector<int> faces;
    for (const PyramidWindow& w : narrow.pyramidWindows)
        if (w.level == 0) faces.push_back(w.faceCount);
    EXPECT_EQ(faces, (std::vector<int>{100, 100, 100, 84}));
    // The layers a device makes, cube-map arrays, and batchSize's range.
    d.maxImageArrayLayers = 256;
    EXPECT_THROW(planFilter(s, d), ProbeError); // 384 layers
    s.batchSize = 42;
    EXPECT_NO_THROW(planFilter(s, d));
    d.imageCubeArray = false;
    EXPECT_THROW(planFilter(s, d), ProbeError);
}

TEST(FilterPlan, RefusesWhatTheDeviceCannotHold) {
    const auto refusal = [](const FilterSettings& s, const DeviceCapabilities& d) {
        try {
            planFilter(s, d);
        } catch (const ProbeError& e) {
            return std::string(e.what());
        }
        return std::string("planned");
    };
    FilterSettings s = fisSettings(2048);
    s.sampling = Sampling::exact;
    // A texel buffer of fewer elements than the pyramid's 33.6 million texels.
    DeviceCapabilities few = gpu();
    few.maxTexelBufferElements = 1u << 25;
    EXPECT_NE(refusal(s, few).find("texel buffers of at most 33554432 texels"), std::string::npos) << refusal(s, few);
    // A storage-buffer range smaller than one face of level 0 (64.1 MiB).
    DeviceCapabilities narrow = gpu();
    narrow.maxStorageBufferRange = 1u << 25;
    EXPECT_NE(refusal(s, narrow).find("storage buffers of at most 32.0 MiB"), std::string::npos) << refusal(s, narrow);
    // Hardware sampling computes its directions and keeps its pyramid in an image: it fits both.
    s.sampling = Sampling::hardware;
    EXPECT_EQ(refusal(s, few), "planned");
    EXPECT_EQ(refusal(s, narrow), "planned");
    // FIS on the paraboloid map reads the source and the map as one texel buffer of 70.0 million texels.
    FilterSettings paraboloid = fisSettings(2048);
    paraboloid.method.fis.map = FisMap::paraboloid;
    DeviceCapabilities fewer = gpu();
    fewer.maxTexelBufferElements = 1u << 26;
    EXPECT_NE(refusal(paraboloid, fewer).find("at most 67108864 texels, this one has 69954242"), std::string::npos)
        << refusal(paraboloid, fewer);
    EXPECT_EQ(refusal(paraboloid, gpu()), "planned");
    // The reference's running sums are a storage buffer of every output level.
    FilterSettings reference = fisSettings(2048);
    reference.method.kind = MethodKind::reference;
    EXPECT_NE(refusal(reference, gpu()).find("maxStorageBufferRange"), std::string::npos) << refusal(reference, gpu());

    // The table method's exact sampling needs subgroup votes.
    TapTable table;
    table.faceSize = 16;
    table.levelCount = 4;
    table.taps = 4;
    table.form = TableForm::constant;
    table.levels.resize(4);
    for (TableLevel& level : table.levels) level.coefficients.assign(std::size_t(table.coefficientsPerLevel()), 0.0);
    FilterSettings t = fisSettings(16);
    t.method = {MethodKind::table, &table, {}};
    t.sampling = Sampling::exact;
    DeviceCapabilities noVote = gpu();
    noVote.computeSubgroupVote = false;
    EXPECT_THROW(planFilter(t, noVote), ProbeError);
    t.sampling = Sampling::hardware;
    EXPECT_NO_THROW(planFilter(t, noVote));
}

TEST(FilterPlan, RefusesSettingsNamingThem) {
    const auto field = [](FilterSettings s) {
        try {
            planFilter(s, gpu());
        } catch (const ParameterError& e) {
            return e.parameter;
        }
        return std::string("none");
    };
    FilterSettings s = fisSettings(64);
    s.inFlight = 0;
    EXPECT_EQ(field(s), "inFlight");
    s = fisSettings(64);
    s.batchSize = 0;
    EXPECT_EQ(field(s), "batchSize");
    s.batchSize = 257;
    EXPECT_EQ(field(s), "batchSize");
    s = fisSettings(64);
    s.method.kind = MethodKind::reference;
    s.batchSize = 2;
    EXPECT_EQ(field(s), "batchSize");
    s = fisSettings(64);
    s.computedLevels = {2, 1};
    EXPECT_EQ(field(s), "computedLevels");
    s = fisSettings(64);
    s.pyramidDepth = 7;
    EXPECT_EQ(field(s), "pyramidDepth");
    s = fisSettings(64);
    s.sampling = Sampling::exact;
    s.pyramidFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
    EXPECT_EQ(field(s), "pyramidFormat");
}

} // namespace
