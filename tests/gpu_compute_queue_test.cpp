// The runtime on a compute-only queue, as an engine's async compute queue is. The test device's
// families all do graphics (lavapipe's one family does), so tests/compute_only_layer reports them
// without VK_QUEUE_GRAPHICS_BIT, below the validation layer: that layer then judges every command,
// pipeline stage and access the runtime records against a queue of compute and transfer alone, as it
// would on a GPU's async compute family. On that queue every path (the tool's run(), record() into
// the engine's command buffer, batches, slices, BC6H, SH, the spheres) gives the test device's bits,
// and the layer reports nothing.
#include <cstring>

#include <fmt/format.h>

#include "engine_caller.h"
#include "gpu_test_support.h"
#include "probe/dfg.h"
#include "probe/error.h"
#include "probe/sh.h"
#include "probe/synthetic.h"
#include "probe/table_io.h"

using namespace probe;
using namespace probetest;

namespace {

constexpr const char* kLayers[] = {"VK_LAYER_KHRONOS_validation", "VK_LAYER_PROBEFILTER_compute_only"};

VKAPI_ATTR VkBool32 VKAPI_CALL collect(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                       const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    static_cast<std::vector<std::string>*>(user)->emplace_back(data->pMessage ? data->pMessage : "(no message)");
    return VK_FALSE;
}

// The engine's instance and device, the test device's physical device seen through the layer, and
// a queue of its first compute family; the validation layer's messages.
class ComputeOnlyDevice {
public:
    ComputeOnlyDevice() {
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.apiVersion = VK_API_VERSION_1_2;
        const VkValidationFeatureEnableEXT synchronization = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
        const VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT, nullptr, 1, &synchronization, 0, nullptr};
        const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, &features};
        info.pApplicationInfo = &app;
        info.enabledLayerCount = 2; // in this order: the validation layer sees the families as the test layer reports them
        info.ppEnabledLayerNames = kLayers;
        info.enabledExtensionCount = 1;
        info.ppEnabledExtensionNames = &extension;
        if (vkCreateInstance(&info, nullptr, &instance) != VK_SUCCESS)
            throw ProbeError("no instance with the validation layer and VK_LAYER_PROBEFILTER_compute_only (VK_ADD_LAYER_PATH)");

        VkDebugUtilsMessengerCreateInfoEXT messengerInfo{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        messengerInfo.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        messengerInfo.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
        messengerInfo.pfnUserCallback = collect;
        messengerInfo.pUserData = &messages;
        auto createMessenger =
            reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
        createMessenger(instance, &messengerInfo, nullptr, &messenger);

        uint32_t count = 0;
        vkEnumeratePhysicalDevices(instance, &count, nullptr);
        std::vector<VkPhysicalDevice> physicals(count);
        vkEnumeratePhysicalDevices(instance, &count, physicals.data());
        for (VkPhysicalDevice p : physicals) {
            VkPhysicalDeviceProperties properties;
            vkGetPhysicalDeviceProperties(p, &properties);
            if (testDevice().info().name == properties.deviceName) physical = p;
        }
        if (!physical) throw ProbeError(fmt::format("{} is not among the layer's devices", testDevice().info().name));

        vkGetPhysicalDeviceQueueFamilyProperties(physical, &count, nullptr);
        families.resize(count);
        vkGetPhysicalDeviceQueueFamilyProperties(physical, &count, families.data());
        while (family < count && !(families[family].queueFlags & VK_QUEUE_COMPUTE_BIT)) ++family;
        if (family == count) throw ProbeError("no compute family");

        const float priority = 1.0f;
        VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        queueInfo.queueFamilyIndex = family;
        queueInfo.queueCount = 1;
        queueInfo.pQueuePriorities = &priority;
        VkPhysicalDeviceFeatures enabled{};
        enabled.imageCubeArray = VK_TRUE;
        VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        features12.timelineSemaphore = VK_TRUE;
        VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features12};
        deviceInfo.pEnabledFeatures = &enabled;
        deviceInfo.queueCreateInfoCount = 1;
        deviceInfo.pQueueCreateInfos = &queueInfo;
        if (vkCreateDevice(physical, &deviceInfo, nullptr, &device) != VK_SUCCESS) throw ProbeError("vkCreateDevice");
        vkGetDeviceQueue(device, family, 0, &queue);
    }
    ~ComputeOnlyDevice() {
        vkDestroyDevice(device, nullptr);
        auto destroy =
            reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
        destroy(instance, messenger, nullptr);
        vkDestroyInstance(instance, nullptr);
    }
    ComputeOnlyDevice(const ComputeOnlyDevice&) = delete;
    ComputeOnlyDevice& operator=(const ComputeOnlyDevice&) = delete;

    Caller caller() const { return {device, physical, family, queue}; }

    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    std::vector<VkQueueFamilyProperties> families;
    uint32_t family = 0;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    std::vector<std::string> messages;
};

// Every test here fails on a message of the validation layer of either device.
class ComputeQueueTest : public GpuTest {
protected:
    void TearDown() override {
        for (const std::string& message : compute.messages) ADD_FAILURE() << "validation (compute-only queue): " << message;
        GpuTest::TearDown();
    }

    ComputeOnlyDevice compute;
};

// The levels of `settings` from `source` through record() into the engine's cubes of `c`,
// in one recording or in the filter's `sliceCount` slices, a submission each.
CubeLevels recordLevels(const Caller& c, gpu::Filter& filter, const gpu::FilterSettings& settings, const std::vector<CubeImage>& sources,
                        int sliceCount = 0) {
    const EngineProbe probe(c, sources, settings.levelCount, VK_FORMAT_R32G32B32A32_SFLOAT, settings.outputFormat);
    EngineCommands commands(c);
    probe.upload(commands.cmd);
    gpu::Completion done;
    if (sliceCount == 0) done = filter.record(commands.cmd, probe.source(), probe.output());
    for (const gpu::Slice& slice : sliceCount ? filter.slices(sliceCount) : std::vector<gpu::Slice>{})
        commands.submit(filter.record(commands.cmd, probe.source(), probe.output(), slice));
    probe.readBack(commands.cmd);
    commands.submit(done);
    CubeLevels all;
    for (std::size_t p = 0; p < sources.size(); ++p)
        for (CubeImage& level : probe.levels(int(p))) all.push_back(std::move(level));
    return all;
}

} // namespace

// The check itself: the family the runtime gets has compute and no graphics, and the validation
// layer judges a command buffer of it as a compute queue's (a fragment-stage barrier is an error).
TEST_F(ComputeQueueTest, TheValidationLayerSeesAComputeOnlyFamily) {
    for (const VkQueueFamilyProperties& f : compute.families) EXPECT_FALSE(f.queueFlags & VK_QUEUE_GRAPHICS_BIT);
    ASSERT_TRUE(compute.families[compute.family].queueFlags & VK_QUEUE_COMPUTE_BIT);
    const Caller c = compute.caller();
    const gpu::Device wrapped(compute.instance, c.physical, c.device, c.queueFamily, c.queue);
    EXPECT_EQ(wrapped.queueFamily(), compute.family);

    EngineCommands commands(c);
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT};
    vkCmdPipelineBarrier(commands.cmd, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &barrier, 0,
                         nullptr, 0, nullptr);
    vkEndCommandBuffer(commands.cmd);
    EXPECT_FALSE(compute.messages.empty()) << "a fragment-stage barrier on a compute-only queue went unreported";
    compute.messages.clear();
}

// The tool path and the engine path, every method and both sampling modes (hardware sampling over
// the default pyramid and the E5B9G9R9 one), a batch of two, three slices, and a Filter initialized in
// the engine's command buffer: the test device's levels, bit for bit.
TEST_F(ComputeQueueTest, FilterEqualsTheTestDevice) {
    const Caller c = compute.caller();
    const gpu::Device wrapped(compute.instance, c.physical, c.device, c.queueFamily, c.queue);
    const TapTable table = readTable(PROBE_TEST_FIXTURES "/table_16_quad4_gltf.json");
    const std::vector<CubeImage> sources = {probetest::randomProbe(16, 31), probetest::randomProbe(16, 32)};
    struct Case {
        gpu::Sampling sampling;
        VkFormat pyramid;
    };
    const Case cases[] = {{gpu::Sampling::exact, VK_FORMAT_UNDEFINED},
                          {gpu::Sampling::hardware, VK_FORMAT_UNDEFINED},
                          {gpu::Sampling::hardware, VK_FORMAT_E5B9G9R9_UFLOAT_PACK32}};
    for (MethodKind method : {MethodKind::table, MethodKind::fis, MethodKind::reference})
        for (const Case& k : cases) {
            if (method == MethodKind::reference && k.sampling == gpu::Sampling::hardware) continue;
            gpu::FilterSettings s;
            s.method = {method, &table, {}};
            s.faceSize = 16;
            s.levelCount = 4;
            s.sampling = k.sampling;
            s.pyramidFormat = k.pyramid;
            s.outputFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
            const std::string what = fmt::format("{} {}{}", methodKindName(method), gpu::samplingName(k.sampling),
                                                 k.pyramid == VK_FORMAT_UNDEFINED ? "" : " over rgb9e5");
            const CubeLevels expected = gpu::Filter(testDevice(), s).run(sources[0]);
            gpu::Filter filter(wrapped, s);
            const CubeLevels ran = filter.run(sources[0]);
            const CubeLevels recorded = recordLevels(c, filter, s, {sources[0]});
            const CubeLevels sliced = recordLevels(c, filter, s, {sources[0]}, 3);
            for (int m = 0; m < s.levelCount; ++m) {
                EXPECT_EQ(ran[m].rgb, expected[m].rgb) << what << ": run, level " << m;
                EXPECT_EQ(recorded[m].rgb, expected[m].rgb) << what << ": record, level " << m;
                EXPECT_EQ(sliced[m].rgb, expected[m].rgb) << what << ": slices, level " << m;
            }
            if (method == MethodKind::reference) continue;
            s.batchSize = 2;
            gpu::Filter batch(wrapped, s);
            const CubeLevels both = recordLevels(c, batch, s, sources);
            gpu::FilterSettings one = s;
            one.batchSize = 1;
            const CubeLevels second = gpu::Filter(testDevice(), one).run(sources[1]);
            for (int m = 0; m < s.levelCount; ++m) {
                EXPECT_EQ(both[m].rgb, expected[m].rgb) << what << ": batch, probe 0, level " << m;
                EXPECT_EQ(both[s.levelCount + m].rgb, second[m].rgb) << what << ": batch, probe 1, level " << m;
            }
        }

    gpu::FilterSettings s;
    s.method.kind = MethodKind::fis;
    s.faceSize = 16;
    s.levelCount = 4;
    const CubeLevels expected = gpu::Filter(testDevice(), s).run(sources[0]);
    EngineCommands init(c);
    gpu::Filter filter(wrapped, s, init.cmd);
    init.submit({});
    const CubeLevels recorded = recordLevels(c, filter, s, {sources[0]});
    for (int m = 0; m < s.levelCount; ++m) EXPECT_EQ(recorded[m].rgb, expected[m].rgb) << "initialized by the engine, level " << m;
}

// What else the runtime submits or records: BC6H (encode() and record() after the filter), the SH
// projection and the sphere renderer give the test device's bits.
TEST_F(ComputeQueueTest, Bc6hShAndSpheresEqualTheTestDevice) {
    const Caller c = compute.caller();
    const gpu::Device wrapped(compute.instance, c.physical, c.device, c.queueFamily, c.queue);
    gpu::FilterSettings s;
    s.method.kind = MethodKind::fis;
    s.faceSize = 16;
    s.levelCount = 5;
    const CubeImage source = sunSkyProbe(s.faceSize);
    const CubeLevels levels = gpu::Filter(testDevice(), s).run(source);

    const std::vector<std::vector<uint8_t>> blocks = gpu::Bc6hEncoder(testDevice(), s.faceSize, s.levelCount).encode(levels);
    gpu::Bc6hEncoder encoder(wrapped, s.faceSize, s.levelCount);
    EXPECT_EQ(encoder.encode(levels), blocks);

    // record(): the filter's output cube into the engine's BC6H cube, read back.
    gpu::Filter filter(wrapped, s);
    const EngineProbe probe(c, source, s.levelCount, VK_FORMAT_R32G32B32A32_SFLOAT, s.outputFormat);
    const EngineBc6hCube bc6h(c, s.faceSize, s.levelCount);
    EngineCommands commands(c);
    probe.upload(commands.cmd);
    bc6h.prepare(commands.cmd);
    const gpu::Completion done = filter.record(commands.cmd, probe.source(), probe.output(), gpu::Timestamps::none);
    encoder.record(commands.cmd, probe.output(), bc6h.image());
    bc6h.readBack(commands.cmd);
    commands.submit(done);
    for (int m = 0; m < s.levelCount; ++m) EXPECT_EQ(bc6h.level(m), blocks[m]) << "BC6H recorded, level " << m;

    const ShCoefficients sh = gpu::ShProjector(wrapped, s.faceSize).project(source);
    const ShCoefficients expectedSh = gpu::ShProjector(testDevice(), s.faceSize).project(source);
    for (int k = 0; k < 9; ++k)
        for (int channel = 0; channel < 3; ++channel) EXPECT_EQ(sh[k][channel], expectedSh[k][channel]) << "SH coefficient " << k;

    const Image dfg = dfgTable(16, 64);
    gpu::SphereScene scene;
    scene.prefiltered = &levels;
    scene.background = &source;
    scene.irradiance = radianceToIrradiance(expectedSh);
    scene.dfg = &dfg;
    scene.materials = {gpu::SphereMaterial{}, gpu::SphereMaterial{glm::vec3(1.0f), 1.0f, 1.0f, 0.2f, 1.0f}};
    scene.cellSize = 16;
    EXPECT_EQ(gpu::renderSpheres(wrapped, scene).rgb, gpu::renderSpheres(testDevice(), scene).rgb);
}
