// What the engine-path tests do as an engine would, with plain Vulkan around probe::gpu::Filter: its
// device and queue, host-visible buffers, cube images, layout transitions, texels in its formats, and
// submissions that signal a Filter's Completion.
#pragma once

#include <cstring>

#include <glm/gtc/packing.hpp>
#include <gtest/gtest.h>
#include <vulkan/vulkan.h>

#include "probe/runtime.h"

namespace probetest {

// Minimal caller-side Vulkan: what an engine already has.
struct Caller {
    VkDevice device;
    VkPhysicalDevice physical;
    uint32_t queueFamily;
    VkQueue queue;

    uint32_t memoryType(uint32_t bits, VkMemoryPropertyFlags flags) const {
        VkPhysicalDeviceMemoryProperties memory;
        vkGetPhysicalDeviceMemoryProperties(physical, &memory);
        for (uint32_t t = 0; t < memory.memoryTypeCount; ++t)
            if ((bits & (1u << t)) && (memory.memoryTypes[t].propertyFlags & flags) == flags) return t;
        ADD_FAILURE() << "no memory type";
        return 0;
    }
    VkDeviceMemory allocate(VkMemoryRequirements r, VkMemoryPropertyFlags flags) const {
        VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, nullptr, r.size, memoryType(r.memoryTypeBits, flags)};
        VkDeviceMemory memory = VK_NULL_HANDLE;
        EXPECT_EQ(vkAllocateMemory(device, &info, nullptr, &memory), VK_SUCCESS);
        return memory;
    }
};

struct HostBuffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    float* data = nullptr;
};

inline HostBuffer hostBuffer(const Caller& c, VkDeviceSize bytes) {
    HostBuffer b;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = bytes;
    info.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    EXPECT_EQ(vkCreateBuffer(c.device, &info, nullptr, &b.buffer), VK_SUCCESS);
    VkMemoryRequirements r;
    vkGetBufferMemoryRequirements(c.device, b.buffer, &r);
    b.memory = c.allocate(r, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    vkBindBufferMemory(c.device, b.buffer, b.memory, 0);
    void* mapped = nullptr;
    vkMapMemory(c.device, b.memory, 0, VK_WHOLE_SIZE, 0, &mapped);
    b.data = static_cast<float*>(mapped);
    return b;
}

struct CubeTexture {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
};

inline CubeTexture cubeTexture(const Caller& c, VkFormat format, int size, int mips, VkImageUsageFlags usage) {
    CubeTexture t;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.flags = VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT;
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {uint32_t(size), uint32_t(size), 1};
    info.mipLevels = uint32_t(mips);
    info.arrayLayers = 6;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    EXPECT_EQ(vkCreateImage(c.device, &info, nullptr, &t.image), VK_SUCCESS);
    VkMemoryRequirements r;
    vkGetImageMemoryRequirements(c.device, t.image, &r);
    t.memory = c.allocate(r, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    vkBindImageMemory(c.device, t.image, t.memory, 0);
    return t;
}

inline void transition(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to, VkAccessFlags srcAccess,
                       VkAccessFlags dstAccess) {
    VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    barrier.srcAccessMask = srcAccess;
    barrier.dstAccessMask = dstAccess;
    barrier.oldLayout = from;
    barrier.newLayout = to;
    barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = image;
    barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0, 6};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, nullptr, 0, nullptr, 1,
                         &barrier);
}

// The probe as the caller's RGBA16F texels hold it.
inline probe::CubeImage halfRounded(const probe::CubeImage& cube) {
    probe::CubeImage rounded = cube;
    for (float& v : rounded.rgb) v = glm::unpackHalf1x16(glm::packHalf1x16(v));
    return rounded;
}

// Bytes per texel of the caller's cubes: RGBA16F or RGBA32F.
inline std::size_t texelBytes(VkFormat format) {
    return format == VK_FORMAT_R16G16B16A16_SFLOAT ? 4 * sizeof(uint16_t) : 4 * sizeof(float);
}

inline void storeTexel(unsigned char* at, VkFormat format, glm::vec3 v) {
    if (format == VK_FORMAT_R16G16B16A16_SFLOAT) {
        const uint16_t rgba[4] = {glm::packHalf1x16(v.r), glm::packHalf1x16(v.g), glm::packHalf1x16(v.b), glm::packHalf1x16(1.0f)};
        std::memcpy(at, rgba, sizeof(rgba));
    } else {
        const float rgba[4] = {v.r, v.g, v.b, 1.0f};
        std::memcpy(at, rgba, sizeof(rgba));
    }
}

inline glm::vec3 loadTexel(const unsigned char* at, VkFormat format) {
    if (format == VK_FORMAT_R16G16B16A16_SFLOAT) {
        uint16_t rgba[4];
        std::memcpy(rgba, at, sizeof(rgba));
        return {glm::unpackHalf1x16(rgba[0]), glm::unpackHalf1x16(rgba[1]), glm::unpackHalf1x16(rgba[2])};
    }
    float rgba[4];
    std::memcpy(rgba, at, sizeof(rgba));
    return {rgba[0], rgba[1], rgba[2]};
}

// Submits `commandBuffer` (ended), signalling `done` where it has a semaphore, and waits for the
// queue.
inline void submitAndWait(VkQueue queue, VkCommandBuffer commandBuffer, const probe::gpu::Completion& done = {}) {
    VkTimelineSemaphoreSubmitInfo timeline{VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO};
    timeline.signalSemaphoreValueCount = 1;
    timeline.pSignalSemaphoreValues = &done.value;
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO, done.semaphore ? &timeline : nullptr};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &commandBuffer;
    submit.signalSemaphoreCount = done.semaphore ? 1 : 0;
    submit.pSignalSemaphores = &done.semaphore;
    EXPECT_EQ(vkQueueSubmit(queue, 1, &submit, VK_NULL_HANDLE), VK_SUCCESS);
    EXPECT_EQ(vkQueueWaitIdle(queue), VK_SUCCESS);
}

} // namespace probetest
