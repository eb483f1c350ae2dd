#include "shader_stats.h"

#include <algorithm>
#include <cstring>
#include <map>

#include <engine_pyramid.spv.h>
#include <engine_table_filter.spv.h>
#include <fmt/format.h>
#include <shader_list.h>

#include "compute_pipeline.h"
#include "filter_descriptors.h"
#include "probe/error.h"
#include "probe/shared_constants.h"
#include "vulkan_check.h"

namespace probe::stats {

namespace {

bool startsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// table_filter.comp's constant_id 0 (kCoefficientCount), 1 (kFixedTapGroups) and 2 (kTaps).
constexpr int32_t kQuadCoefficients = 3, kConstantCoefficients = 1;
// FIS's samples and the table's tap groups per frame in the two compilations of a loop cost; every
// table compilation has the taps per frame of the larger.
constexpr int kSamplesA = 8, kSamplesB = 16;
constexpr int kTapGroupsA = 2, kTapGroupsB = 4;
constexpr int32_t kTableTaps = 4 * kTapGroupsB;

} // namespace

std::vector<ShaderVariant> runtimeVariants() {
#define PROBE_SPIRV(name, spirv) {#name, spirv},
    const std::pair<std::string, std::span<const uint32_t>> shaders[] = {PROBE_SHADER_LIST(PROBE_SPIRV)};
#undef PROBE_SPIRV
    std::vector<ShaderVariant> variants;
    for (const auto& [shader, spirv] : shaders) {
        if (startsWith(shader, "table_filter_")) {
            variants.push_back({shader + " quad", spirv, {kQuadCoefficients, 0, kTableTaps}});
            variants.push_back({shader + " const", spirv, {kConstantCoefficients, 0, kTableTaps}});
        } else if (shader == "pyramid" || startsWith(shader, "pyramid_image_") ||
                   startsWith(shader, "pyramid_tail_")) { // kBoxKind, kInverseSolidAngle
            variants.push_back({shader + " bspline", spirv, {0, 0}});
            variants.push_back({shader + " box", spirv, {1, 0}});
        } else {
            variants.push_back({shader, spirv, {}});
        }
    }
    variants.push_back({"engine/probe_pyramid gltf128_quad8", kEnginePyramidSpv, {}});
    variants.push_back({"engine/probe_table_filter gltf128_quad8", kEngineTableFilterSpv, {}});
    return variants;
}

std::vector<LoopVariant> loopVariants() {
    // Frames in the code: hardware sampling inlines addTableFrame three times, exact sampling loops over
    // the frames with one copy (table_filter.comp); each pass of the tap loop takes a group of four.
    const int hardwareFrames = 3, exactFrames = 1;
    std::vector<LoopVariant> loops;
    for (const auto& [form, coefficients] : {std::pair{"quad", kQuadCoefficients}, std::pair{"const", kConstantCoefficients}})
        for (const auto& [sampling, spirv, frames] :
             {std::tuple{"hardware", std::span<const uint32_t>(kTableFilterHardwareRgba32fSpv), hardwareFrames},
              std::tuple{"exact", std::span<const uint32_t>(kTableFilterExactRgba32fSpv), exactFrames}})
            loops.push_back({fmt::format("table_filter_{}_rgba32f {}", sampling, form),
                             "tap",
                             spirv,
                             {coefficients, 0, kTableTaps},
                             {coefficients, kTapGroupsA, kTableTaps},
                             {coefficients, kTapGroupsB, kTableTaps},
                             4 * kTapGroupsA * frames,
                             4 * kTapGroupsB * frames,
                             4 * frames});
    for (const auto& [sampling, spirv] : {std::pair{"hardware", std::span<const uint32_t>(kFisHardwareRgba32fSpv)},
                                          std::pair{"exact", std::span<const uint32_t>(kFisExactRgba32fSpv)},
                                          std::pair{"paraboloid", std::span<const uint32_t>(kFisParaboloidRgba32fSpv)}})
        loops.push_back({fmt::format("fis_{}_rgba32f", sampling), "sample", spirv, {}, {kSamplesA}, {kSamplesB}, kSamplesA, kSamplesB, 1});
    return loops;
}

// The interior of a face, max(|u|, |v|) <= PROBE_FRAME_BAND_START, takes two frames; the ring around
// it three.
double tableFramesPerTexel() { return 3.0 - PROBE_FRAME_BAND_START * PROBE_FRAME_BAND_START; }

struct StatisticsDevice::Impl {
    VkInstance instance = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    std::string name, driver;
    PFN_vkGetPipelineExecutablePropertiesKHR executableProperties = nullptr;
    PFN_vkGetPipelineExecutableStatisticsKHR executableStatistics = nullptr;
    PFN_vkGetPipelineExecutableInternalRepresentationsKHR executableRepresentations = nullptr;
    std::unique_ptr<gpu::FilterDescriptors> layout;
};

namespace {

bool reportsStatistics(VkPhysicalDevice physical) {
    uint32_t count = 0;
    vkEnumerateDeviceExtensionProperties(physical, nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> extensions(count);
    vkEnumerateDeviceExtensionProperties(physical, nullptr, &count, extensions.data());
    for (const VkExtensionProperties& e : extensions)
        if (std::strcmp(e.extensionName, VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME) == 0) return true;
    return false;
}

int64_t statisticValue(const VkPipelineExecutableStatisticKHR& s) {
    switch (s.format) {
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR: return s.value.b32;
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR: return s.value.i64;
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR: return static_cast<int64_t>(s.value.u64);
    default: return static_cast<int64_t>(s.value.f64);
    }
}

// The vector memory instructions of RADV's disassembly, one instruction per line.
int64_t countVectorMemory(std::string_view disassembly) {
    static constexpr std::string_view kPrefixes[] = {"buffer_", "tbuffer_", "image_", "global_", "flat_", "scratch_"};
    int64_t count = 0;
    std::size_t start = 0;
    while (start < disassembly.size()) {
        std::size_t end = disassembly.find('\n', start);
        if (end == std::string_view::npos) end = disassembly.size();
        std::string_view line = disassembly.substr(start, end - start);
        start = end + 1;
        line.remove_prefix(std::min(line.find_first_not_of(" \t"), line.size()));
        for (std::string_view prefix : kPrefixes)
            if (line.starts_with(prefix)) ++count;
    }
    return count;
}

} // namespace

StatisticsDevice::StatisticsDevice() : impl_(std::make_unique<Impl>()) {
    Impl& d = *impl_;
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "shader_stats";
    app.apiVersion = VK_API_VERSION_1_2;
    VkInstanceCreateInfo instanceInfo{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    instanceInfo.pApplicationInfo = &app;
    gpu::vkCheck(vkCreateInstance(&instanceInfo, nullptr, &d.instance), "vkCreateInstance");

    uint32_t count = 0;
    vkEnumeratePhysicalDevices(d.instance, &count, nullptr);
    std::vector<VkPhysicalDevice> physicals(count);
    vkEnumeratePhysicalDevices(d.instance, &count, physicals.data());
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    for (VkPhysicalDevice p : physicals)
        if (reportsStatistics(p)) {
            physical = p;
            break;
        }
    if (!physical) {
        vkDestroyInstance(d.instance, nullptr);
        throw ProbeError(
            "Vulkan: no device reports pipeline statistics (VK_KHR_pipeline_executable_properties); bench/scripts/shader-stats "
            "selects RADV's null device (Debian: mesa-vulkan-drivers)");
    }
    VkPhysicalDeviceDriverProperties driverProperties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties.pNext = &driverProperties;
    vkGetPhysicalDeviceProperties2(physical, &properties);
    d.name = properties.properties.deviceName;
    d.driver = fmt::format("{} {}", driverProperties.driverName, driverProperties.driverInfo);

    // A queue is required to create the device; nothing is submitted to it.
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = 0;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;
    VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR executableFeatures{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
    executableFeatures.pipelineExecutableInfo = VK_TRUE;
    const char* extension = VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME;
    VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    deviceInfo.pNext = &executableFeatures;
    deviceInfo.queueCreateInfoCount = 1;
    deviceInfo.pQueueCreateInfos = &queueInfo;
    deviceInfo.enabledExtensionCount = 1;
    deviceInfo.ppEnabledExtensionNames = &extension;
    if (const VkResult result = vkCreateDevice(physical, &deviceInfo, nullptr, &d.device); result != VK_SUCCESS) {
        vkDestroyInstance(d.instance, nullptr);
        gpu::vkCheck(result, "vkCreateDevice");
    }
    d.executableProperties =
        reinterpret_cast<PFN_vkGetPipelineExecutablePropertiesKHR>(vkGetDeviceProcAddr(d.device, "vkGetPipelineExecutablePropertiesKHR"));
    d.executableStatistics =
        reinterpret_cast<PFN_vkGetPipelineExecutableStatisticsKHR>(vkGetDeviceProcAddr(d.device, "vkGetPipelineExecutableStatisticsKHR"));
    d.executableRepresentations = reinterpret_cast<PFN_vkGetPipelineExecutableInternalRepresentationsKHR>(
        vkGetDeviceProcAddr(d.device, "vkGetPipelineExecutableInternalRepresentationsKHR"));
    // The Filter's pipeline layout: its bindings 0-4 are shaders/buffers.glsl's, which the SH projector
    // and the sphere renderer bind too, so one layout serves every shader; its written mips are as
    // many as the wide level groups declare (RADV and lavapipe offer them).
    d.layout = std::make_unique<gpu::FilterDescriptors>(d.device, gpu::kWideWrittenMipCount);
}

StatisticsDevice::~StatisticsDevice() {
    impl_->layout.reset();
    vkDestroyDevice(impl_->device, nullptr);
    vkDestroyInstance(impl_->instance, nullptr);
}

std::string StatisticsDevice::name() const { return impl_->name; }
std::string StatisticsDevice::driver() const { return impl_->driver; }

PipelineStatistics StatisticsDevice::compile(std::span<const uint32_t> spirv, std::span<const int32_t> specialization) const {
    const Impl& d = *impl_;
    const gpu::ComputePipeline pipeline(d.device, d.layout->pipelineLayout(), spirv, specialization,
                                        VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR |
                                            VK_PIPELINE_CREATE_CAPTURE_INTERNAL_REPRESENTATIONS_BIT_KHR);
    VkPipelineInfoKHR pipelineInfo{VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR};
    pipelineInfo.pipeline = pipeline.handle();
    uint32_t executables = 0;
    gpu::vkCheck(d.executableProperties(d.device, &pipelineInfo, &executables, nullptr), "vkGetPipelineExecutablePropertiesKHR");
    if (executables != 1) throw ProbeError(fmt::format("Vulkan: a compute pipeline with {} executables", executables));

    VkPipelineExecutableInfoKHR executable{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR};
    executable.pipeline = pipeline.handle();
    executable.executableIndex = 0;
    uint32_t count = 0;
    gpu::vkCheck(d.executableStatistics(d.device, &executable, &count, nullptr), "vkGetPipelineExecutableStatisticsKHR");
    std::vector<VkPipelineExecutableStatisticKHR> statistics(count, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR});
    gpu::vkCheck(d.executableStatistics(d.device, &executable, &count, statistics.data()), "vkGetPipelineExecutableStatisticsKHR");

    // RADV's names for them.
    PipelineStatistics result;
    const std::map<std::string, int64_t*> fields{{"Instructions", &result.instructions},
                                                 {"VGPRs", &result.vgprs},
                                                 {"SGPRs", &result.sgprs},
                                                 {"Spilled VGPRs", &result.spilledVgprs},
                                                 {"Spilled SGPRs", &result.spilledSgprs},
                                                 {"Latency", &result.latency},
                                                 {"Inverse Throughput", &result.inverseThroughput}};
    for (const VkPipelineExecutableStatisticKHR& s : statistics)
        if (const auto field = fields.find(s.name); field != fields.end()) *field->second = statisticValue(s);

    // RADV names its disassembly "Assembly"; other drivers leave the count at -1.
    gpu::vkCheck(d.executableRepresentations(d.device, &executable, &count, nullptr), "vkGetPipelineExecutableInternalRepresentationsKHR");
    std::vector<VkPipelineExecutableInternalRepresentationKHR> representations(
        count, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INTERNAL_REPRESENTATION_KHR});
    gpu::vkCheck(d.executableRepresentations(d.device, &executable, &count, representations.data()),
                 "vkGetPipelineExecutableInternalRepresentationsKHR");
    std::vector<std::string> texts(count);
    for (uint32_t i = 0; i < count; ++i) {
        texts[i].resize(representations[i].dataSize);
        representations[i].pData = texts[i].data();
    }
    gpu::vkCheck(d.executableRepresentations(d.device, &executable, &count, representations.data()),
                 "vkGetPipelineExecutableInternalRepresentationsKHR");
    for (uint32_t i = 0; i < count; ++i)
        if (std::strcmp(representations[i].name, "Assembly") == 0) result.vectorMemory = countVectorMemory(texts[i]);
    return result;
}

LoopCost measureLoop(const StatisticsDevice& device, const LoopVariant& loop) {
    return {loop, device.compile(loop.spirv, loop.runtime), device.compile(loop.spirv, loop.fixedA),
            device.compile(loop.spirv, loop.fixedB)};
}

} // namespace probe::stats
