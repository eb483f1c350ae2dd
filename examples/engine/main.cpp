// An engine filtering a probe with probefilter: it owns the Vulkan instance, device, queue, images
// and command buffer; the filter records its passes between the engine's own upload and readback.
// The probe is a synthetic sun and sky in an RGBA16F cube; the output is an RGBA16F cube with a mip
// per roughness. Checks the result against the CPU model of the same table, and its error against
// the exact GGX reference against the model's own. Exit code 0 only if both hold.
//
// Usage: engine_example [hardware|exact]   (default: the runtime's choice for the device)
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/gtc/packing.hpp>
#include <vulkan/vulkan.h>

#include "probe/cpu_filter.h"
#include "probe/error_measures.h"
#include "probe/reference.h"
#include "probe/runtime.h"
#include "probe/synthetic.h"

namespace {

constexpr int kFaceSize = 32;
constexpr VkFormat kFormat = VK_FORMAT_R16G16B16A16_SFLOAT;

void check(VkResult result, const char* what) {
    if (result != VK_SUCCESS) throw std::runtime_error(std::string(what) + " failed: VkResult " + std::to_string(result));
}

uint32_t validationMessages = 0;

VKAPI_ATTR VkBool32 VKAPI_CALL onValidation(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                            const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
    std::fprintf(stderr, "validation: %s\n", data->pMessage);
    ++validationMessages;
    return VK_FALSE;
}

bool hasLayer(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    for (const VkLayerProperties& l : layers)
        if (std::strcmp(l.layerName, name) == 0) return true;
    return false;
}

struct Engine {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    VkQueue queue = VK_NULL_HANDLE;

    Engine() {
        const bool validation = hasLayer("VK_LAYER_KHRONOS_validation");
        const char* layer = "VK_LAYER_KHRONOS_validation";
        const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.pApplicationName = "engine_example";
        app.apiVersion = VK_API_VERSION_1_2;
        VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        info.pApplicationInfo = &app;
        info.enabledLayerCount = validation ? 1 : 0;
        info.ppEnabledLayerNames = &layer;
        info.enabledExtensionCount = validation ? 1 : 0;
        info.ppEnabledExtensionNames = &extension;
        check(vkCreateInstance(&info, nullptr, &instance), "vkCreateInstance");
        if (validation) {
            VkDebugUtilsMessengerCreateInfoEXT m{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
            m.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
            m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
            m.pfnUserCallback = onValidation;
            auto create =
                reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
            check(create(instance, &m, nullptr, &messenger), "vkCreateDebugUtilsMessengerEXT");
        }
        // The first GPU with a compute queue, else any device with one.
        uint32_t count = 0;
        vkEnumeratePhysicalDevices(instance, &count, nullptr);
        std::vector<VkPhysicalDevice> devices(count);
        vkEnumeratePhysicalDevices(instance, &count, devices.data());
        for (VkPhysicalDevice candidate : devices) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(candidate, &p);
            if (p.apiVersion < VK_API_VERSION_1_2) continue;
            uint32_t familyCount = 0;
            vkGetPhysicalDeviceQueueFamilyProperties(candidate, &familyCount, nullptr);
            std::vector<VkQueueFamilyProperties> families(familyCount);
            vkGetPhysicalDeviceQueueFamilyProperties(candidate, &familyCount, families.data());
            for (uint32_t f = 0; f < familyCount; ++f) {
                if (!(families[f].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
                const bool gpu =
                    p.deviceType == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU || p.deviceType == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU;
                if (physicalDevice == VK_NULL_HANDLE || gpu) {
                    physicalDevice = candidate;
                    queueFamily = f;
                }
                break;
            }
            if (physicalDevice == candidate && p.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU) break;
        }
        if (physicalDevice == VK_NULL_HANDLE) throw std::runtime_error("no Vulkan 1.2 device with a compute queue");
        const float priority = 1.0f;
        VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        queueInfo.queueFamilyIndex = queueFamily;
        queueInfo.queueCount = 1;
        queueInfo.pQueuePriorities = &priority;
        // The one feature the runtime needs: timeline semaphores, which tell a Filter that a recording
        // has completed.
        VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        features12.timelineSemaphore = VK_TRUE;
        VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features12};
        deviceInfo.queueCreateInfoCount = 1;
        deviceInfo.pQueueCreateInfos = &queueInfo;
        check(vkCreateDevice(physicalDevice, &deviceInfo, nullptr, &device), "vkCreateDevice");
        vkGetDeviceQueue(device, queueFamily, 0, &queue);
    }
    ~Engine() {
        vkDestroyDevice(device, nullptr);
        if (messenger) {
            auto destroy =
                reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
            destroy(instance, messenger, nullptr);
        }
        vkDestroyInstance(instance, nullptr);
    }

    VkDeviceMemory allocate(VkMemoryRequirements requirements, VkMemoryPropertyFlags flags) const {
        VkPhysicalDeviceMemoryProperties properties;
        vkGetPhysicalDeviceMemoryProperties(physicalDevice, &properties);
        for (uint32_t t = 0; t < properties.memoryTypeCount; ++t) {
            if (!(requirements.memoryTypeBits & (1u << t)) || (properties.memoryTypes[t].propertyFlags & flags) != flags) continue;
            VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
            info.allocationSize = requirements.size;
            info.memoryTypeIndex = t;
            VkDeviceMemory memory;
            check(vkAllocateMemory(device, &info, nullptr, &memory), "vkAllocateMemory");
            return memory;
        }
        throw std::runtime_error("no suitable memory type");
    }
};

struct CubeTexture {
    const Engine& engine;
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;

    CubeTexture(const Engine& e, int mips, VkImageUsageFlags usage) : engine(e) {
        VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        info.flags = VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT;
        info.imageType = VK_IMAGE_TYPE_2D;
        info.format = kFormat;
        info.extent = {kFaceSize, kFaceSize, 1};
        info.mipLevels = static_cast<uint32_t>(mips);
        info.arrayLayers = 6;
        info.samples = VK_SAMPLE_COUNT_1_BIT;
        info.tiling = VK_IMAGE_TILING_OPTIMAL;
        info.usage = usage;
        check(vkCreateImage(e.device, &info, nullptr, &image), "vkCreateImage");
        VkMemoryRequirements requirements;
        vkGetImageMemoryRequirements(e.device, image, &requirements);
        memory = e.allocate(requirements, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        check(vkBindImageMemory(e.device, image, memory, 0), "vkBindImageMemory");
        VkImageViewCreateInfo v{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        v.image = image;
        v.viewType = VK_IMAGE_VIEW_TYPE_CUBE;
        v.format = kFormat;
        v.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, static_cast<uint32_t>(mips), 0, 6};
        check(vkCreateImageView(e.device, &v, nullptr, &view), "vkCreateImageView");
    }
    ~CubeTexture() {
        vkDestroyImageView(engine.device, view, nullptr);
        vkDestroyImage(engine.device, image, nullptr);
        vkFreeMemory(engine.device, memory, nullptr);
    }
};

struct HostBuffer {
    const Engine& engine;
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* data = nullptr;

    HostBuffer(const Engine& e, VkDeviceSize size, VkBufferUsageFlags usage) : engine(e) {
        VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        info.size = size;
        info.usage = usage;
        check(vkCreateBuffer(e.device, &info, nullptr, &buffer), "vkCreateBuffer");
        VkMemoryRequirements requirements;
        vkGetBufferMemoryRequirements(e.device, buffer, &requirements);
        memory = e.allocate(requirements, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        check(vkBindBufferMemory(e.device, buffer, memory, 0), "vkBindBufferMemory");
        check(vkMapMemory(e.device, memory, 0, VK_WHOLE_SIZE, 0, &data), "vkMapMemory");
    }
    ~HostBuffer() {
        vkDestroyBuffer(engine.device, buffer, nullptr);
        vkFreeMemory(engine.device, memory, nullptr);
    }
};

void barrier(VkCommandBuffer cmd, VkImage image, uint32_t mips, VkImageLayout from, VkImageLayout to, VkPipelineStageFlags srcStage,
             VkAccessFlags srcAccess, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = srcAccess;
    b.dstAccessMask = dstAccess;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, mips, 0, 6};
    vkCmdPipelineBarrier(cmd, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

std::size_t levelTexels(int level) {
    return 6u * static_cast<std::size_t>(kFaceSize >> level) * static_cast<std::size_t>(kFaceSize >> level);
}

int run(int argc, char** argv) {
    const Engine engine;
    const probe::gpu::Device device(engine.instance, engine.physicalDevice, engine.device, engine.queueFamily, engine.queue);
    const int levels = probe::defaultLevelCount(kFaceSize);

    // The compiled-in table for the size, as probefilter --method table picks it.
    const probe::gpu::CompiledTable* table =
        probe::gpu::findCompiledTable(kFaceSize, levels, probe::RoughnessMapping::gltf, {}, probe::Lobe::ggx);
    if (!table) throw std::runtime_error("no compiled-in table for 32^2");
    probe::gpu::FilterSettings settings;
    settings.method = {probe::MethodKind::table, &table->table, {}};
    settings.faceSize = kFaceSize;
    settings.levelCount = levels;
    settings.outputFormat = kFormat;
    if (argc > 1) settings.sampling = probe::gpu::parseSampling(argv[1]);

    // The probe, rounded to half as the engine stores it.
    probe::CubeImage source = probe::sunSkyProbe(kFaceSize);
    std::vector<uint16_t> halves;
    for (std::size_t t = 0; t < levelTexels(0); ++t) {
        for (int c = 0; c < 3; ++c) halves.push_back(glm::packHalf1x16(source.rgb[3 * t + c]));
        halves.push_back(glm::packHalf1x16(1.0f));
    }
    for (std::size_t k = 0; k < source.rgb.size(); ++k) source.rgb[k] = glm::unpackHalf1x16(halves[k / 3 * 4 + k % 3]);

    CubeTexture sourceCube(engine, 1, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
    CubeTexture outputCube(engine, levels, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    std::size_t outputTexels = 0;
    for (int m = 0; m < levels; ++m) outputTexels += levelTexels(m);
    HostBuffer upload(engine, halves.size() * sizeof(uint16_t), VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
    HostBuffer readback(engine, outputTexels * 4 * sizeof(uint16_t), VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    std::memcpy(upload.data, halves.data(), halves.size() * sizeof(uint16_t));
    // After the images: the filter keeps views of them until it ends.
    probe::gpu::Filter filter(device, settings);

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.queueFamilyIndex = engine.queueFamily;
    VkCommandPool pool;
    check(vkCreateCommandPool(engine.device, &poolInfo, nullptr, &pool), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo allocation{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    allocation.commandPool = pool;
    allocation.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    allocation.commandBufferCount = 1;
    VkCommandBuffer cmd;
    check(vkAllocateCommandBuffers(engine.device, &allocation, &cmd), "vkAllocateCommandBuffers");
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");

    // The engine's work: upload the probe.
    barrier(cmd, sourceCube.image, 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
            VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 6};
    copy.imageExtent = {kFaceSize, kFaceSize, 1};
    vkCmdCopyBufferToImage(cmd, upload.buffer, sourceCube.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    // What the filter needs (runtime.h, Filter::record): the source readable by compute shaders,
    // the output mips in GENERAL.
    barrier(cmd, sourceCube.image, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
            VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    barrier(cmd, outputCube.image, static_cast<uint32_t>(levels), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
            VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT);
    // The cubes as the engine made them, which record() checks.
    const probe::gpu::SourceCube sourceDescription{sourceCube.view, kFormat, VK_IMAGE_VIEW_TYPE_CUBE, kFaceSize};
    const probe::gpu::OutputCube outputDescription{outputCube.image,
                                                   kFormat,
                                                   kFaceSize,
                                                   static_cast<uint32_t>(levels),
                                                   6,
                                                   VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                                       VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
    // The submission signals the Completion, so the Filter knows when its resources are free again.
    const probe::gpu::Completion done = filter.record(cmd, sourceDescription, outputDescription);
    // The engine's work again: read every mip back.
    barrier(cmd, outputCube.image, static_cast<uint32_t>(levels), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    VkDeviceSize offset = 0;
    for (int m = 0; m < levels; ++m) {
        VkBufferImageCopy back{};
        back.bufferOffset = offset;
        back.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, static_cast<uint32_t>(m), 0, 6};
        back.imageExtent = {static_cast<uint32_t>(kFaceSize >> m), static_cast<uint32_t>(kFaceSize >> m), 1};
        vkCmdCopyImageToBuffer(cmd, outputCube.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.buffer, 1, &back);
        offset += levelTexels(m) * 4 * sizeof(uint16_t);
    }
    VkMemoryBarrier hostRead{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    hostRead.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    hostRead.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &hostRead, 0, nullptr, 0, nullptr);
    check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");

    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    check(vkCreateFence(engine.device, &fenceInfo, nullptr, &fence), "vkCreateFence");
    VkTimelineSemaphoreSubmitInfo timeline{VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO};
    timeline.signalSemaphoreValueCount = 1;
    timeline.pSignalSemaphoreValues = &done.value;
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO, &timeline};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    submit.signalSemaphoreCount = 1;
    submit.pSignalSemaphores = &done.semaphore;
    check(vkQueueSubmit(engine.queue, 1, &submit, fence), "vkQueueSubmit");
    check(vkWaitForFences(engine.device, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
    vkDestroyFence(engine.device, fence, nullptr);
    vkDestroyCommandPool(engine.device, pool, nullptr);

    // The levels as the engine would sample them, against the CPU model of the same table (the
    // runtime's verification mode, in double) and the exact GGX reference.
    const auto* words = static_cast<const uint16_t*>(readback.data);
    const probe::CubeLevels model = probe::filterOnCpu(source, levels, probe::RoughnessMapping::gltf, settings.method);
    const probe::CubeLevels reference = probe::referenceFilter(source, levels, probe::RoughnessMapping::gltf);
    std::printf("device: %s; sampling: %s; table: %s\n", device.info().name.c_str(),
                std::string(probe::gpu::samplingName(filter.sampling())).c_str(), table->name.c_str());
    std::printf("level  image L1 vs the table's CPU model  vs the exact reference (the model's)\n");
    // RGBA16F holds 11 significant bits (5e-4 relative); the hardware sampler's sub-texel weights
    // (8 fractional bits on common GPUs) add up to 2e-3 relative to neighbouring texel differences.
    const double modelTolerance = 3e-3;
    bool ok = validationMessages == 0;
    for (int m = 0; m < levels; ++m) {
        probe::CubeImage level(kFaceSize >> m);
        for (std::size_t t = 0; t < levelTexels(m); ++t)
            for (int c = 0; c < 3; ++c) level.rgb[3 * t + c] = glm::unpackHalf1x16(words[4 * t + static_cast<std::size_t>(c)]);
        words += 4 * levelTexels(m);
        const double toModel = probe::imageL1(level, model[m]), toReference = probe::imageL1(level, reference[m]);
        // As close to the reference as the table itself gets, up to the model tolerance.
        const double modelToReference = probe::imageL1(model[m], reference[m]);
        bool finite = true;
        for (float v : level.rgb) finite = finite && std::isfinite(v);
        ok = ok && finite && toModel <= modelTolerance && toReference <= modelToReference + modelTolerance;
        std::printf("%5d  %33.2e  %21.4f (%.4f)%s\n", m, toModel, toReference, modelToReference, finite ? "" : "  (not finite)");
    }
    std::printf("%s (model tolerance %.0e, %u validation messages)\n", ok ? "PASS" : "FAIL", modelTolerance, validationMessages);
    return ok ? 0 : 1;
}

} // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "engine_example: %s\n", e.what());
        return 2;
    }
}
