// The Vulkan objects behind probe::gpu::Device, shared by the runtime's sources.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "probe/runtime.h"

namespace probe::gpu {

struct Device::Impl {
    bool owned = false; // created here (destroyed here) or the caller's
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    VkQueue queue = VK_NULL_HANDLE;
    DeviceInfo info;
    VkPhysicalDeviceLimits limits{};
    VkPhysicalDeviceMemoryProperties memory{};
    uint32_t timestampValidBits = 0;
    bool computeSubgroupVote = false; // subgroupAny in compute shaders (table_filter.comp's exact sampling needs it)
    // The imageCubeArray feature, which a batch's cube-map arrays need: enabled on an owned device where
    // it exists; on the engine's device, it exists (enabling it is the engine's part).
    bool imageCubeArray = false;
    // Optimal-tiling features of the formats the runtime uses, read once (tests may clear bits to
    // stand in for a device that lacks them).
    std::map<VkFormat, VkFormatFeatureFlags> formatFeatures;

    // The optimal-tiling features of `format`.
    VkFormatFeatureFlags features(VkFormat format) const;

    mutable std::mutex messagesMutex;
    std::vector<std::string> messages;

    // What destroyed Filters' recordings in flight read, each kept until `semaphore` reaches `value`.
    struct Retired {
        std::shared_ptr<void> resources;
        VkSemaphore semaphore;
        uint64_t value;
    };
    std::vector<Retired> retired;
    void retire(std::shared_ptr<void> resources, VkSemaphore semaphore, uint64_t value);
    // Releases the retired resources whose recordings have completed.
    void releaseRetired();

    // A memory type allowed by `typeBits` with all of `required`, preferring one with `preferred` too.
    uint32_t memoryType(uint32_t typeBits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) const;
};

// Name, driver and type of a physical device.
DeviceInfo describePhysicalDevice(VkPhysicalDevice physical, int index);

} // namespace probe::gpu
