// The engine path: Filter::record into the caller's command buffer, on the caller's device (the test
// device wrapped), from the caller's RGBA16F source cube (sampled through its cube view) straight
// into the caller's RGBA16F output mips, gives the same levels as the tool path (Filter::run) on the
// same half-float texels, in both sampling modes, and the validation layer stays silent; an RGBA32F
// source at the largest finite values gives finite levels for every method.
#include <limits>

#include <fmt/format.h>

#include "engine_caller.h"
#include "gpu_test_support.h"
#include "probe/error.h"
#include "probe/range_scale.h"
#include "probe/synthetic.h"
#include "probe/table_io.h"

using namespace probe;
using probetest::GpuTest;
using namespace probetest;

namespace {

// What an engine does around Filter::record: its source cube (of `sourceFormat`, holding `source`)
// uploaded and made readable by compute shaders, its output cube (of the filter's output format,
// RGBA16F or RGBA32F) in GENERAL for the filter's writes, the passes recorded into its command
// buffer between them, the output copied back. Returns the output levels. With `slices`, records
// those one after another instead of the whole update.
CubeLevels recordOnce(const Caller& c, gpu::Filter& engine, const gpu::FilterSettings& settings, const CubeImage& source,
                      VkFormat sourceFormat, gpu::Timestamps timestamps = gpu::Timestamps::passes,
                      const std::vector<gpu::Slice>* slices = nullptr) {
    const EngineProbe probe(c, source, settings.levelCount, sourceFormat, settings.outputFormat);
    EngineCommands commands(c);
    probe.upload(commands.cmd);
    gpu::Completion done;
    if (!slices) done = engine.record(commands.cmd, probe.source(), probe.output(), timestamps);
    // One submission per slice, as frames would run them.
    for (const gpu::Slice& slice : slices ? *slices : std::vector<gpu::Slice>{}) {
        const gpu::Completion sliceDone = engine.record(commands.cmd, probe.source(), probe.output(), slice);
        EXPECT_EQ(engine.dispatches().size(), slice.dispatches) << "the slice's dispatches, known before it was recorded";
        commands.submit(sliceDone);
    }
    probe.readBack(commands.cmd);
    commands.submit(done);
    return probe.levels();
}

// FIS at 32^2, 5 levels, into RGBA16F: what an engine's probe filter might be.
gpu::FilterSettings engineSettings(gpu::Sampling sampling) {
    gpu::FilterSettings settings;
    settings.method.kind = MethodKind::fis;
    settings.faceSize = 32;
    settings.levelCount = 5;
    settings.sampling = sampling;
    settings.outputFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
    return settings;
}

// `count` probes of a batch as an engine's RGBA16F texels hold them.
std::vector<CubeImage> halfProbes(int size, int count, unsigned seed) {
    std::vector<CubeImage> probes;
    for (int p = 0; p < count; ++p) probes.push_back(halfRounded(probetest::randomProbe(size, seed + unsigned(p))));
    return probes;
}

void recordAndCompare(const Caller& c, const gpu::Device& owner, const gpu::Device& wrapped, gpu::Sampling sampling) {
    const gpu::FilterSettings settings = engineSettings(sampling);
    const CubeImage source = halfRounded(probetest::randomProbe(settings.faceSize, 7));
    gpu::Filter tool(owner, settings);
    const CubeLevels expected = tool.run(source);

    gpu::Filter engine(wrapped, settings);
    const CubeLevels recorded = recordOnce(c, engine, settings, source, VK_FORMAT_R16G16B16A16_SFLOAT);
    const std::vector<gpu::PassTime> timings = engine.timings();
    ASSERT_EQ(timings.size(), 3u);
    EXPECT_EQ(timings[0].name, "pyramid");
    EXPECT_GT(timings[2].medianMs, 0.0);
    EXPECT_TRUE(engine.levelTimings().empty()); // record() times passes, not levels
    for (int m = 0; m < settings.levelCount; ++m)
        EXPECT_EQ(recorded[m].rgb, expected[m].rgb) << gpu::samplingName(sampling) << " sampling, level " << m;
}

} // namespace

// An engine's shipping path writes no timestamp queries: the same levels, and no timings.
TEST_F(GpuTest, RecordWithoutTimestamps) {
    const gpu::Device& owner = probetest::testDevice();
    const Caller c = callerOf(owner);
    gpu::FilterSettings settings;
    settings.method.kind = MethodKind::fis;
    settings.faceSize = 32;
    settings.levelCount = 5;
    settings.outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    const CubeImage source = probetest::randomProbe(settings.faceSize, 3);
    gpu::Filter engine(owner, settings);
    const CubeLevels timed = recordOnce(c, engine, settings, source, VK_FORMAT_R32G32B32A32_SFLOAT);
    EXPECT_FALSE(engine.timings().empty());
    const CubeLevels untimed = recordOnce(c, engine, settings, source, VK_FORMAT_R32G32B32A32_SFLOAT, gpu::Timestamps::none);
    EXPECT_TRUE(engine.timings().empty());
    for (int m = 0; m < settings.levelCount; ++m) EXPECT_EQ(untimed[m].rgb, timed[m].rgb) << "level " << m;
}

TEST_F(GpuTest, RecordIntoCallersCommandBufferEqualsRun) {
    const gpu::Device& owner = probetest::testDevice();
    const Caller c = callerOf(owner);
    const gpu::Device wrapped(owner.instance(), c.physical, c.device, c.queueFamily, c.queue);
    for (gpu::Sampling sampling : {gpu::Sampling::exact, gpu::Sampling::hardware}) recordAndCompare(c, owner, wrapped, sampling);
}

// A batch recorded as an engine keeps probes: an RGBA16F cube-map array of three probes in, an
// 18-layer output written in one recording through a wrapped device, each probe's levels those of a
// Filter of one probe, in both sampling modes, in the dispatches of one probe; and in three slices,
// a submission each, the same levels.
TEST_F(GpuTest, RecordABatchIntoTheEnginesCubeMapArrays) {
    const gpu::Device& owner = probetest::testDevice();
    const Caller c = callerOf(owner);
    gpu::Device wrapped(owner.instance(), c.physical, c.device, c.queueFamily, c.queue);
    for (gpu::Sampling sampling : {gpu::Sampling::exact, gpu::Sampling::hardware}) {
        gpu::FilterSettings settings = engineSettings(sampling);
        const std::vector<CubeImage> sources = halfProbes(settings.faceSize, 3, 20);
        gpu::Filter alone(owner, settings);
        settings.batchSize = int(sources.size());
        gpu::Filter batch(wrapped, settings);
        const EngineProbe probes(c, sources, settings.levelCount, VK_FORMAT_R16G16B16A16_SFLOAT, settings.outputFormat);
        // The output as the Filter sizes it: what the engine's is, and an image the device makes.
        const VkImageCreateInfo info = batch.outputImageInfo();
        const gpu::OutputCube output = probes.output();
        EXPECT_EQ(info.format, output.format);
        EXPECT_EQ(info.extent.width, output.faceSize);
        EXPECT_EQ(info.extent.height, output.faceSize);
        EXPECT_EQ(info.mipLevels, output.mipLevels);
        EXPECT_EQ(info.arrayLayers, output.arrayLayers);
        EXPECT_EQ(output.usage & info.usage & ~VkImageUsageFlags(VK_IMAGE_USAGE_SAMPLED_BIT), VK_IMAGE_USAGE_STORAGE_BIT);
        VkImage made = VK_NULL_HANDLE;
        EXPECT_EQ(vkCreateImage(c.device, &info, nullptr, &made), VK_SUCCESS);
        vkDestroyImage(c.device, made, nullptr);
        EngineCommands commands(c);
        probes.upload(commands.cmd);
        const gpu::Completion done = batch.record(commands.cmd, probes.source(), probes.output(), gpu::Timestamps::none);
        probes.readBack(commands.cmd);
        commands.submit(done);
        for (int p = 0; p < int(sources.size()); ++p) {
            const CubeLevels expected = alone.run(sources[std::size_t(p)]);
            const CubeLevels recorded = probes.levels(p);
            for (int m = 0; m < settings.levelCount; ++m)
                EXPECT_EQ(recorded[m].rgb, expected[m].rgb) << gpu::samplingName(sampling) << " sampling, probe " << p << ", level " << m;
        }
        EXPECT_EQ(batch.dispatches().size(), alone.dispatches().size()) << gpu::samplingName(sampling);

        // The same batch spread over three frames: a slice a submission, the same bits.
        const EngineProbe sliced(c, sources, settings.levelCount, VK_FORMAT_R16G16B16A16_SFLOAT, settings.outputFormat);
        sliced.upload(commands.cmd);
        for (const gpu::Slice& slice : batch.slices(3)) {
            const gpu::Completion sliceDone = batch.record(commands.cmd, sliced.source(), sliced.output(), slice);
            EXPECT_EQ(batch.dispatches().size(), slice.dispatches);
            commands.submit(sliceDone);
        }
        sliced.readBack(commands.cmd);
        commands.submit({});
        for (int p = 0; p < int(sources.size()); ++p)
            for (int m = 0; m < settings.levelCount; ++m)
                EXPECT_EQ(sliced.levels(p)[m].rgb, probes.levels(p)[m].rgb)
                    << gpu::samplingName(sampling) << " sampling, sliced, probe " << p << ", level " << m;
    }
}

// A batch of the engine's separately allocated cubes: three RGBA16F source cubes and three output
// cubes, copied into the Filter's arrays and out of them around the passes of one probe: each probe's
// levels those of a Filter of one probe, in both sampling modes, in the dispatches of one probe and
// three barriers more (the copies'); what the copies cannot take is refused by field.
TEST_F(GpuTest, RecordABatchOfSeparateCubes) {
    const gpu::Device& owner = probetest::testDevice();
    const Caller c = callerOf(owner);
    gpu::Device wrapped(owner.instance(), c.physical, c.device, c.queueFamily, c.queue);
    for (gpu::Sampling sampling : {gpu::Sampling::exact, gpu::Sampling::hardware}) {
        gpu::FilterSettings settings = engineSettings(sampling);
        const std::vector<CubeImage> sources = halfProbes(settings.faceSize, 3, 30);
        gpu::Filter alone(owner, settings);
        settings.batchSize = int(sources.size());
        gpu::Filter batch(wrapped, settings);
        std::vector<std::unique_ptr<EngineProbe>> probes;
        std::vector<gpu::SourceCube> in;
        std::vector<gpu::OutputCube> out;
        for (const CubeImage& source : sources) {
            probes.push_back(
                std::make_unique<EngineProbe>(c, source, settings.levelCount, VK_FORMAT_R16G16B16A16_SFLOAT, settings.outputFormat));
            in.push_back(probes.back()->source());
            out.push_back(probes.back()->output());
        }
        EngineCommands commands(c);
        for (const auto& probe : probes) probe->upload(commands.cmd, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        const gpu::Completion done = batch.record(commands.cmd, in, out, gpu::Timestamps::none);
        for (const auto& probe : probes) probe->readBack(commands.cmd, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        commands.submit(done);
        for (std::size_t p = 0; p < sources.size(); ++p) {
            const CubeLevels expected = alone.run(sources[p]);
            for (int m = 0; m < settings.levelCount; ++m)
                EXPECT_EQ(probes[p]->levels()[m].rgb, expected[m].rgb)
                    << gpu::samplingName(sampling) << " sampling, probe " << p << ", level " << m;
        }
        EXPECT_EQ(batch.dispatches().size(), alone.dispatches().size()) << gpu::samplingName(sampling);
        EXPECT_EQ(batch.barriers(), alone.barriers() + 3) << gpu::samplingName(sampling);

        const auto refused = [&](std::vector<gpu::SourceCube> s, std::vector<gpu::OutputCube> o, const std::string& field) {
            try {
                (void)batch.record(commands.cmd, s, o);
                ADD_FAILURE() << field << " accepted";
            } catch (const ProbeError& e) {
                EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
            }
        };
        refused({in[0], in[1]}, out, "sources holds 2 cubes");
        refused(in, {out[0]}, "outputs holds 1 cubes");
        std::vector<gpu::SourceCube> s = in;
        s[1].image = VK_NULL_HANDLE;
        refused(s, out, "sources[1].image");
        s = in;
        s[0].usage = VK_IMAGE_USAGE_SAMPLED_BIT;
        refused(s, out, "sources[0].usage");
        s = in;
        s[2].format = VK_FORMAT_R32G32B32A32_SFLOAT;
        refused(s, out, "sources[2].format");
        s = in;
        s[0].arrayLayers = 12;
        refused(s, out, "sources[0].arrayLayers");
        std::vector<gpu::OutputCube> o = out;
        o[2].usage = VK_IMAGE_USAGE_STORAGE_BIT;
        refused(in, o, "outputs[2].usage");
        o = out;
        o[1].mipLevels = 2;
        refused(in, o, "outputs[1].mipLevels");
        commands.submit({});
    }
}

// Finite input gives finite output on the engine path too, where the source never reaches the host:
// the caller's RGBA32F source holding FLT_MAX, -FLT_MAX, 0 and -0 side by side gives finite levels
// for every method and sampling mode, into RGBA32F and RGBA16F outputs. The source saturates at
// +-kFilterRangeLimit (2^64) where the passes read it, and at 65504 in hardware sampling's default
// RGBA16F pyramid, so an all-FLT_MAX source gives 2^64 at every level (65504 in RGBA16F), 65504 at
// the levels read from a half pyramid (all but level 0, the source's copy), and no level exceeds
// that in magnitude.
TEST_F(GpuTest, RecordLargestFiniteValuesEveryMethod) {
    const gpu::Device& owner = probetest::testDevice();
    const Caller c = callerOf(owner);
    const gpu::Device wrapped(owner.instance(), c.physical, c.device, c.queueFamily, c.queue);
    const TapTable table = readTable(PROBE_TEST_FIXTURES "/table_16_quad4_gltf.json");
    constexpr float largest = std::numeric_limits<float>::max();
    const CubeImage allLargest(table.faceSize, glm::vec3(largest));
    CubeImage mixed(table.faceSize);
    for (std::size_t t = 0; t < texelCount(mixed.size); ++t) {
        const float values[4] = {largest, 0.0f, -largest, -0.0f};
        mixed.set(t, {values[t % 4], values[(t + 1) % 4], values[(t + 2) % 4]});
    }
    // FIS over every pyramid (the inverse solid angle weighs a coarse texel's children by up to
    // S_0^2), on the paraboloid map, the table over its own pyramid, and the reference.
    std::vector<std::pair<std::string, FilterMethod>> methods{{"table", {MethodKind::table, &table, {}}}};
    for (PyramidKind kind : {PyramidKind::bspline, PyramidKind::box})
        for (PyramidWeighting weighting : {PyramidWeighting::solidAngle, PyramidWeighting::inverseSolidAngle}) {
            FilterMethod fis{MethodKind::fis, nullptr, {}};
            fis.fis.pyramid = {kind, weighting};
            methods.emplace_back(fmt::format("fis {} {}", pyramidKindName(kind), pyramidWeightingName(weighting)), fis);
        }
    FilterMethod paraboloid{MethodKind::fis, nullptr, {}};
    paraboloid.fis.map = FisMap::paraboloid;
    methods.emplace_back("fis paraboloid", paraboloid);
    methods.emplace_back("reference", FilterMethod{MethodKind::reference, nullptr, {}});
    for (VkFormat outputFormat : {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT})
        for (const auto& [name, method] : methods)
            for (gpu::Sampling sampling : {gpu::Sampling::exact, gpu::Sampling::hardware}) {
                // The paraboloid map and the reference read their input exactly whatever the setting.
                const bool readsExactly = name == "fis paraboloid" || name == "reference";
                if (sampling == gpu::Sampling::hardware && readsExactly) continue;
                gpu::FilterSettings settings;
                settings.method = method;
                settings.faceSize = table.faceSize;
                settings.levelCount = table.levelCount;
                settings.mapping = table.mapping;
                settings.sampling = sampling;
                settings.outputFormat = outputFormat;
                gpu::Filter engine(wrapped, settings);
                const float outputLimit = outputFormat == VK_FORMAT_R16G16B16A16_SFLOAT ? 65504.0f : kFilterRangeLimit;
                const bool halfPyramid =
                    engine.sampling() == gpu::Sampling::hardware && engine.pyramidFormat() == VK_FORMAT_R16G16B16A16_SFLOAT;
                const std::string what =
                    fmt::format("{}, {} sampling, {} output", name, gpu::samplingName(sampling), gpu::formatName(outputFormat));
                const CubeLevels fromLargest = recordOnce(c, engine, settings, allLargest, VK_FORMAT_R32G32B32A32_SFLOAT);
                const CubeLevels fromMixed = recordOnce(c, engine, settings, mixed, VK_FORMAT_R32G32B32A32_SFLOAT);
                for (int m = 0; m < settings.levelCount; ++m) {
                    const bool fromHalf = halfPyramid && m > 0;
                    const float limit = fromHalf ? std::min(outputLimit, 65504.0f) : outputLimit;
                    const double tolerance = fromHalf ? 0x1p-10 : 1e-5; // a half's rounding
                    for (float v : fromLargest[m].rgb)
                        ASSERT_TRUE(std::isfinite(v) && std::abs(v - limit) <= tolerance * limit)
                            << what << ", all FLT_MAX, level " << m << ": " << v;
                    for (float v : fromMixed[m].rgb)
                        ASSERT_TRUE(std::isfinite(v) && std::abs(v) <= limit * (1.0 + 1e-5))
                            << what << ", +-FLT_MAX and +-0, level " << m << ": " << v;
                }
            }
}

// record() checks the cubes as the engine describes them and refuses a mismatch naming the field,
// before anything is recorded: a 2D or 2D-array view, a source or output of another face size, an
// output with fewer mips than levels or not 6 layers, without storage usage, or of another format,
// and null handles; for a batch, a source that is not a cube-map array of its layers, or an output of
// other layers.
TEST_F(GpuTest, RecordRefusesCubesThatDoNotMatch) {
    gpu::FilterSettings settings;
    settings.method.kind = MethodKind::fis;
    settings.faceSize = 32;
    settings.levelCount = 6;
    settings.outputFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
    gpu::Filter filter(probetest::testDevice(), settings);
    // Handles that are never used: every case is refused before anything is recorded.
    const auto fake = [](auto handle) { return reinterpret_cast<decltype(handle)>(std::uintptr_t{0x1000}); };
    const VkCommandBuffer cmd = fake(VkCommandBuffer{});
    const gpu::SourceCube source{fake(VkImageView{}), VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_VIEW_TYPE_CUBE, 32};
    const gpu::OutputCube output{fake(VkImage{}), VK_FORMAT_R16G16B16A16_SFLOAT, 32, 6, 6, VK_IMAGE_USAGE_STORAGE_BIT};
    struct Case {
        const char* field;
        gpu::SourceCube source;
        gpu::OutputCube output;
    };
    std::vector<Case> cases;
    const auto withSource = [&](const char* field, auto change) {
        gpu::SourceCube s = source;
        change(s);
        cases.push_back({field, s, output});
    };
    const auto withOutput = [&](const char* field, auto change) {
        gpu::OutputCube o = output;
        change(o);
        cases.push_back({field, source, o});
    };
    withSource("source.view", [](gpu::SourceCube& s) { s.view = VK_NULL_HANDLE; });
    withSource("source.viewType", [](gpu::SourceCube& s) { s.viewType = VK_IMAGE_VIEW_TYPE_2D; });
    withSource("source.viewType", [](gpu::SourceCube& s) { s.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY; });
    withSource("source.viewType", [](gpu::SourceCube& s) { s.viewType = VK_IMAGE_VIEW_TYPE_MAX_ENUM; }); // not described
    withSource("source.faceSize", [](gpu::SourceCube& s) { s.faceSize = 16; });
    withSource("source.format", [](gpu::SourceCube& s) { s.format = VK_FORMAT_UNDEFINED; });
    withOutput("output.image", [](gpu::OutputCube& o) { o.image = VK_NULL_HANDLE; });
    withOutput("output.format", [](gpu::OutputCube& o) { o.format = VK_FORMAT_R32G32B32A32_SFLOAT; });
    withOutput("output.faceSize", [](gpu::OutputCube& o) { o.faceSize = 64; });
    withOutput("output.mipLevels", [](gpu::OutputCube& o) { o.mipLevels = 4; });
    withOutput("output.arrayLayers", [](gpu::OutputCube& o) { o.arrayLayers = 1; });
    withOutput("output.usage", [](gpu::OutputCube& o) { o.usage = VK_IMAGE_USAGE_SAMPLED_BIT; });
    for (const Case& c : cases) {
        try {
            (void)filter.record(cmd, c.source, c.output);
            ADD_FAILURE() << c.field << ": not refused";
        } catch (const ProbeError& e) {
            EXPECT_NE(std::string(e.what()).find(c.field), std::string::npos) << e.what();
        }
    }
    try {
        (void)filter.record(VK_NULL_HANDLE, source, output);
        ADD_FAILURE() << "a null command buffer: not refused";
    } catch (const ProbeError& e) {
        EXPECT_NE(std::string(e.what()).find("commandBuffer"), std::string::npos) << e.what();
    }
    // A batch of three reads a cube-map array view of 18 layers and writes 18 layers: one cube, a
    // cube view or an array of another size is refused.
    settings.batchSize = 3;
    gpu::Filter batch(probetest::testDevice(), settings);
    const gpu::SourceCube sources{fake(VkImageView{}), VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_VIEW_TYPE_CUBE_ARRAY, 32, 18};
    const gpu::OutputCube outputs{fake(VkImage{}), VK_FORMAT_R16G16B16A16_SFLOAT, 32, 6, 18, VK_IMAGE_USAGE_STORAGE_BIT};
    const std::vector<Case> batchCases{{"source.viewType", source, outputs},
                                       {"source.arrayLayers", {sources.view, sources.format, sources.viewType, 32, 6}, outputs},
                                       {"source.arrayLayers", {sources.view, sources.format, sources.viewType, 32, 24}, outputs},
                                       {"output.arrayLayers", sources, output}};
    for (const Case& c : batchCases) {
        try {
            (void)batch.record(cmd, c.source, c.output);
            ADD_FAILURE() << c.field << ": not refused in a batch";
        } catch (const ProbeError& e) {
            EXPECT_NE(std::string(e.what()).find(c.field), std::string::npos) << e.what();
        }
    }
}

// A Filter built through the engine's pipeline cache gives the levels of one built without it, and
// the cache stays usable. (Whether the driver stores the pipelines there is its choice: lavapipe
// keeps its cache empty, so the test device cannot show that it was read.)
TEST_F(GpuTest, FilterBuildsItsPipelinesThroughTheEnginesCache) {
    const gpu::Device& device = probetest::testDevice();
    VkPipelineCacheCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
    VkPipelineCache cache = VK_NULL_HANDLE;
    ASSERT_EQ(vkCreatePipelineCache(device.device(), &info, nullptr, &cache), VK_SUCCESS);
    const auto cacheBytes = [&] {
        std::size_t bytes = 0;
        EXPECT_EQ(vkGetPipelineCacheData(device.device(), cache, &bytes, nullptr), VK_SUCCESS);
        return bytes;
    };
    const std::size_t empty = cacheBytes();
    gpu::FilterSettings settings;
    settings.method.kind = MethodKind::fis;
    settings.faceSize = 16;
    settings.levelCount = 4;
    const CubeImage source = probetest::randomProbe(16, 9);
    const CubeLevels plain = gpu::Filter(device, settings).run(source);
    settings.pipelineCache = cache;
    const CubeLevels cached = gpu::Filter(device, settings).run(source);
    EXPECT_GE(cacheBytes(), empty);
    for (int m = 0; m < settings.levelCount; ++m) EXPECT_EQ(cached[m].rgb, plain[m].rgb) << "level " << m;
    vkDestroyPipelineCache(device.device(), cache, nullptr);
}

// A Filter built without a submission of its own: its initialization recorded into the engine's
// command buffer, which the engine submits before the first record(). Its levels are run()'s, at the
// first record and at the second (when it frees the initialization's staging memory).
TEST_F(GpuTest, FilterInitializedInTheEnginesCommandBuffer) {
    const gpu::Device& owner = probetest::testDevice();
    const Caller c = callerOf(owner);
    const gpu::Device wrapped(owner.instance(), c.physical, c.device, c.queueFamily, c.queue);
    gpu::FilterSettings settings;
    settings.method.kind = MethodKind::fis;
    settings.faceSize = 32;
    settings.levelCount = 5;
    settings.sampling = gpu::Sampling::hardware;
    settings.outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    const CubeImage source = probetest::randomProbe(settings.faceSize, 13);
    const CubeLevels expected = gpu::Filter(owner, settings).run(source);

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.queueFamilyIndex = c.queueFamily;
    VkCommandPool pool = VK_NULL_HANDLE;
    ASSERT_EQ(vkCreateCommandPool(c.device, &poolInfo, nullptr, &pool), VK_SUCCESS);
    VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, nullptr, pool, VK_COMMAND_BUFFER_LEVEL_PRIMARY, 1};
    VkCommandBuffer init = VK_NULL_HANDLE;
    ASSERT_EQ(vkAllocateCommandBuffers(c.device, &allocate, &init), VK_SUCCESS);
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    vkBeginCommandBuffer(init, &begin);
    gpu::Filter engine(wrapped, settings, init);
    vkEndCommandBuffer(init);
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &init;
    ASSERT_EQ(vkQueueSubmit(c.queue, 1, &submit, VK_NULL_HANDLE), VK_SUCCESS);
    ASSERT_EQ(vkQueueWaitIdle(c.queue), VK_SUCCESS);
    vkDestroyCommandPool(c.device, pool, nullptr);

    for (int recording = 0; recording < 2; ++recording) {
        const CubeLevels recorded = recordOnce(c, engine, settings, source, VK_FORMAT_R32G32B32A32_SFLOAT);
        for (int m = 0; m < settings.levelCount; ++m)
            EXPECT_EQ(recorded[m].rgb, expected[m].rgb) << "recording " << recording << ", level " << m;
    }
    EXPECT_THROW(gpu::Filter(wrapped, settings, VK_NULL_HANDLE), ProbeError);
}

// Time slicing: an update recorded as slices (the pyramid, then the levels in groups) writes the same
// bits as one recording of the whole, for every method and both sampling modes; the slices' costs,
// known before recording, are what they dispatch (recordOnce checks each), and they cover every level
// once.
TEST_F(GpuTest, SlicesEqualTheWholeUpdate) {
    const gpu::Device& device = probetest::testDevice();
    const Caller c = callerOf(device);
    const TapTable table = readTable(PROBE_TEST_FIXTURES "/table_16_quad4_gltf.json");
    const CubeImage source = probetest::randomProbe(16, 11);
    for (MethodKind method : {MethodKind::table, MethodKind::fis, MethodKind::reference})
        for (gpu::Sampling sampling : {gpu::Sampling::exact, gpu::Sampling::hardware}) {
            if (method == MethodKind::reference && sampling == gpu::Sampling::hardware) continue;
            gpu::FilterSettings s;
            s.method = {method, &table, {}};
            s.faceSize = 16;
            s.levelCount = 4;
            s.sampling = sampling;
            s.outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
            gpu::Filter filter(probetest::testDevice(), s);
            const CubeLevels whole = recordOnce(c, filter, s, source, VK_FORMAT_R32G32B32A32_SFLOAT);
            const std::size_t wholeDispatches = filter.dispatches().size();
            for (int count : {1, 2, 3, 8}) {
                const std::vector<gpu::Slice> slices = filter.slices(count);
                const std::string what = fmt::format("{} {} in {} slices", methodKindName(method), gpu::samplingName(sampling), count);
                ASSERT_LE(slices.size(), std::size_t(count)) << what;
                EXPECT_TRUE(slices.front().pyramid) << what;
                std::vector<int> levels;
                uint32_t dispatches = 0;
                for (const gpu::Slice& slice : slices) {
                    levels.insert(levels.end(), slice.levels.begin(), slice.levels.end());
                    dispatches += slice.dispatches;
                    EXPECT_GT(slice.texelTaps, 0.0) << what;
                }
                EXPECT_EQ(levels, (std::vector<int>{0, 1, 2, 3})) << what;
                // A level group that the slices split costs a dispatch per part.
                if (count == 1) EXPECT_EQ(dispatches, wholeDispatches) << what;
                else EXPECT_GE(dispatches, wholeDispatches) << what;
                const CubeLevels sliced = recordOnce(c, filter, s, source, VK_FORMAT_R32G32B32A32_SFLOAT, gpu::Timestamps::none, &slices);
                for (int m = 0; m < 4; ++m) EXPECT_EQ(sliced[m].rgb, whole[m].rgb) << what << ": level " << m;
            }
            EXPECT_THROW(filter.slices(0), ProbeError);
        }
}

// BC6H made by the engine in the same submission as the filter: Bc6hEncoder::record after
// Filter::record, from the engine's output cube (RGBA16F and RGBA32F) into its BC6H cube, gives the
// bytes that encode() gives for the same levels, under the validation layer; a source the encoder
// cannot read is refused by the field's name.
TEST_F(GpuTest, Bc6hRecordedAfterTheFilterEqualsEncode) {
    const gpu::Device& device = probetest::testDevice();
    const Caller c = callerOf(device);
    for (VkFormat format : {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT}) {
        gpu::FilterSettings settings;
        settings.method.kind = MethodKind::fis;
        settings.faceSize = 16;
        settings.levelCount = 5; // down to 1x1: a level under 4x4 fills one block
        settings.outputFormat = format;
        gpu::Filter filter(device, settings);
        gpu::Bc6hEncoder encoder(device, settings.faceSize, settings.levelCount);
        const EngineProbe probe(c, sunSkyProbe(settings.faceSize), settings.levelCount, VK_FORMAT_R32G32B32A32_SFLOAT, format);
        const EngineBc6hCube bc6h(c, settings.faceSize, settings.levelCount);
        EngineCommands commands(c);
        probe.upload(commands.cmd);
        bc6h.prepare(commands.cmd);
        const gpu::Completion done = filter.record(commands.cmd, probe.source(), probe.output(), gpu::Timestamps::none);
        encoder.record(commands.cmd, probe.output(), bc6h.image());
        bc6h.readBack(commands.cmd);
        probe.readBack(commands.cmd);
        commands.submit(done);

        const std::vector<std::vector<uint8_t>> expected = encoder.encode(probe.levels());
        for (int m = 0; m < settings.levelCount; ++m)
            EXPECT_EQ(bc6h.level(m), expected[m]) << gpu::formatName(format) << " output, level " << m;

        gpu::OutputCube wrong = probe.output();
        wrong.usage = VK_IMAGE_USAGE_STORAGE_BIT;
        const auto refusedField = [&](const gpu::OutputCube& source, VkImage target) {
            try {
                encoder.record(commands.cmd, source, target);
            } catch (const ProbeError& e) {
                return std::string(e.what());
            }
            return std::string("nothing refused");
        };
        EXPECT_NE(refusedField(wrong, bc6h.image()).find("source.usage"), std::string::npos);
        wrong = probe.output();
        wrong.mipLevels = 3;
        EXPECT_NE(refusedField(wrong, bc6h.image()).find("source.mipLevels"), std::string::npos);
        wrong = probe.output();
        wrong.format = VK_FORMAT_B10G11R11_UFLOAT_PACK32;
        EXPECT_NE(refusedField(wrong, bc6h.image()).find("source.format"), std::string::npos);
        EXPECT_NE(refusedField(probe.output(), VK_NULL_HANDLE).find("target"), std::string::npos);
    }
}
