// What the engine-path tests do as an engine would, with plain Vulkan around probe::gpu::Filter: its
// device and queue, host-visible buffers, cube images, layout transitions, texels in its formats,
// submissions that signal a Filter's Completion, a probe's source and output cubes, and a command
// buffer.
#pragma once

#include <algorithm>
#include <cstring>

#include <glm/gtc/packing.hpp>
#include <gtest/gtest.h>
#include <vulkan/vulkan.h>

#include "gpu_test_support.h"
#include "probe/bc6h.h"
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

inline Caller callerOf(const probe::gpu::Device& device) {
    return {device.device(), device.physicalDevice(), device.queueFamily(), device.queue()};
}

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

inline CubeTexture cubeTexture(const Caller& c, VkFormat format, int size, int mips, VkImageUsageFlags usage, int cubes = 1) {
    CubeTexture t;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.flags = VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT;
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {uint32_t(size), uint32_t(size), 1};
    info.mipLevels = uint32_t(mips);
    info.arrayLayers = uint32_t(6 * cubes);
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
    barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
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

// An engine's probe: its source cube of `sourceFormat` (uploaded by upload()) and output cube of
// `outputFormat` (read back by readBack()), RGBA16F or RGBA32F, with the staging memory for both; or
// a batch of probes, as cube-map arrays (a VK_IMAGE_VIEW_TYPE_CUBE_ARRAY source view).
class EngineProbe {
public:
    EngineProbe(const Caller& c, const probe::CubeImage& source, int levels, VkFormat sourceFormat = VK_FORMAT_R32G32B32A32_SFLOAT,
                VkFormat outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT)
        : EngineProbe(c, std::vector<probe::CubeImage>{source}, levels, sourceFormat, outputFormat) {}
    EngineProbe(const Caller& c, const std::vector<probe::CubeImage>& sources, int levels,
                VkFormat sourceFormat = VK_FORMAT_R32G32B32A32_SFLOAT, VkFormat outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT)
        : c_(c), size_(sources.front().size), levels_(levels), cubes_(int(sources.size())), sourceFormat_(sourceFormat),
          outputFormat_(outputFormat) {
        in_ = cubeTexture(c, sourceFormat, size_, 1, kSourceUsage, cubes_);
        out_ = cubeTexture(c, outputFormat, size_, levels, kOutputUsage, cubes_);
        VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        viewInfo.image = in_.image;
        viewInfo.viewType = viewType();
        viewInfo.format = sourceFormat;
        viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, uint32_t(6 * cubes_)};
        EXPECT_EQ(vkCreateImageView(c.device, &viewInfo, nullptr, &view_), VK_SUCCESS);
        regions_ = levelRegions(size_, levels, texelBytes(outputFormat), cubes_);
        std::size_t outputTexels = 0;
        for (int m = 0; m < levels; ++m) outputTexels += probe::texelCount(size_ >> m);
        const std::size_t cubeTexels = probe::texelCount(size_);
        staging_ = hostBuffer(c, std::max(outputTexels * texelBytes(outputFormat), cubeTexels * texelBytes(sourceFormat)) * sources.size());
        auto* bytes = reinterpret_cast<unsigned char*>(staging_.data);
        for (std::size_t p = 0; p < sources.size(); ++p) // probe p in layers 6p to 6p + 5
            for (std::size_t t = 0; t < cubeTexels; ++t)
                storeTexel(bytes + (p * cubeTexels + t) * texelBytes(sourceFormat), sourceFormat, sources[p].texel(t));
    }
    ~EngineProbe() {
        vkDestroyImageView(c_.device, view_, nullptr);
        vkDestroyBuffer(c_.device, staging_.buffer, nullptr);
        vkFreeMemory(c_.device, staging_.memory, nullptr);
        for (const CubeTexture& t : {in_, out_}) {
            vkDestroyImage(c_.device, t.image, nullptr);
            vkFreeMemory(c_.device, t.memory, nullptr);
        }
    }
    EngineProbe(const EngineProbe&) = delete;
    EngineProbe& operator=(const EngineProbe&) = delete;

    // The usage a batch of separate cubes needs too: its copies read the sources and write the outputs.
    static constexpr VkImageUsageFlags kSourceUsage =
        VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    static constexpr VkImageUsageFlags kOutputUsage =
        VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;

    probe::gpu::SourceCube source() const {
        return {view_, sourceFormat_, viewType(), uint32_t(size_), uint32_t(6 * cubes_), in_.image, kSourceUsage};
    }
    probe::gpu::OutputCube output() const {
        return {out_.image, outputFormat_, uint32_t(size_), uint32_t(levels_), uint32_t(6 * cubes_), kOutputUsage};
    }

    // The source from staging, readable by compute; the output in `outputLayout` for the filter's
    // writes (GENERAL, or TRANSFER_DST_OPTIMAL for its copies into a batch of separate cubes).
    void upload(VkCommandBuffer cmd, VkImageLayout outputLayout = VK_IMAGE_LAYOUT_GENERAL) const {
        transition(cmd, in_.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT);
        VkBufferImageCopy whole{};
        whole.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, uint32_t(6 * cubes_)};
        whole.imageExtent = {uint32_t(size_), uint32_t(size_), 1};
        vkCmdCopyBufferToImage(cmd, staging_.buffer, in_.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &whole);
        transition(cmd, in_.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                   VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT);
        transition(cmd, out_.image, VK_IMAGE_LAYOUT_UNDEFINED, outputLayout, 0, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
    }
    // The output's levels into staging, for the host (after the upload's texels were consumed); the
    // output back in GENERAL for the next recording.
    void readBack(VkCommandBuffer cmd, VkImageLayout outputLayout = VK_IMAGE_LAYOUT_GENERAL) const {
        transition(cmd, out_.image, outputLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                   VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
        vkCmdCopyImageToBuffer(cmd, out_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging_.buffer, uint32_t(regions_.size()),
                               regions_.data());
        transition(cmd, out_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL, VK_ACCESS_TRANSFER_READ_BIT,
                   VK_ACCESS_SHADER_WRITE_BIT);
        VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &toHost, 0, nullptr, 0, nullptr);
    }
    // The levels of probe `cube` of the batch.
    probe::CubeLevels levels(int cube = 0) const {
        probe::CubeLevels result;
        const auto* bytes = reinterpret_cast<const unsigned char*>(staging_.data);
        for (int m = 0; m < levels_; ++m) {
            probe::CubeImage level(size_ >> m);
            const unsigned char* first =
                bytes + regions_[m].bufferOffset + std::size_t(cube) * probe::texelCount(level.size) * texelBytes(outputFormat_);
            for (std::size_t t = 0; t < probe::texelCount(level.size); ++t)
                level.set(t, loadTexel(first + t * texelBytes(outputFormat_), outputFormat_));
            result.push_back(std::move(level));
        }
        return result;
    }

private:
    VkImageViewType viewType() const { return cubes_ > 1 ? VK_IMAGE_VIEW_TYPE_CUBE_ARRAY : VK_IMAGE_VIEW_TYPE_CUBE; }

    const Caller& c_;
    int size_, levels_, cubes_;
    VkFormat sourceFormat_, outputFormat_;
    CubeTexture in_, out_;
    VkImageView view_ = VK_NULL_HANDLE;
    HostBuffer staging_;
    std::vector<VkBufferImageCopy> regions_;
};

// An engine's BC6H cube of `levels` mips (the target of Bc6hEncoder::record) and the host memory its
// blocks are read back into.
class EngineBc6hCube {
public:
    EngineBc6hCube(const Caller& c, int size, int levels) : c_(c) {
        cube_ =
            cubeTexture(c, VK_FORMAT_BC6H_UFLOAT_BLOCK, size, levels, VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
        VkDeviceSize bytes = 0;
        for (int m = 0; m < levels; ++m) {
            const uint32_t levelSize = uint32_t(size >> m);
            regions_.push_back({bytes, 0, 0, {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), 0, 6}, {0, 0, 0}, {levelSize, levelSize, 1}});
            bytes += probe::bc6hLevelBytes(int(levelSize));
        }
        blocks_ = hostBuffer(c, bytes);
    }
    ~EngineBc6hCube() {
        vkDestroyBuffer(c_.device, blocks_.buffer, nullptr);
        vkFreeMemory(c_.device, blocks_.memory, nullptr);
        vkDestroyImage(c_.device, cube_.image, nullptr);
        vkFreeMemory(c_.device, cube_.memory, nullptr);
    }
    EngineBc6hCube(const EngineBc6hCube&) = delete;
    EngineBc6hCube& operator=(const EngineBc6hCube&) = delete;

    VkImage image() const { return cube_.image; }
    // Its mips in TRANSFER_DST_OPTIMAL, as the encoder's record() takes them.
    void prepare(VkCommandBuffer cmd) const {
        transition(cmd, cube_.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT);
    }
    // The encoder's blocks into host memory.
    void readBack(VkCommandBuffer cmd) const {
        transition(cmd, cube_.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                   VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT);
        vkCmdCopyImageToBuffer(cmd, cube_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, blocks_.buffer, uint32_t(regions_.size()),
                               regions_.data());
        VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &toHost, 0, nullptr, 0, nullptr);
    }
    // Level m's blocks, as read back.
    std::vector<uint8_t> level(int m) const {
        const auto* first = reinterpret_cast<const uint8_t*>(blocks_.data) + regions_[std::size_t(m)].bufferOffset;
        return {first, first + probe::bc6hLevelBytes(int(regions_[std::size_t(m)].imageExtent.width))};
    }

private:
    const Caller& c_;
    CubeTexture cube_;
    std::vector<VkBufferImageCopy> regions_;
    HostBuffer blocks_;
};

// One command buffer of the engine's, begun.
class EngineCommands {
public:
    explicit EngineCommands(const Caller& c) : c_(c) {
        VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        poolInfo.queueFamilyIndex = c.queueFamily;
        EXPECT_EQ(vkCreateCommandPool(c.device, &poolInfo, nullptr, &pool_), VK_SUCCESS);
        VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, nullptr, pool_,
                                             VK_COMMAND_BUFFER_LEVEL_PRIMARY, 1};
        EXPECT_EQ(vkAllocateCommandBuffers(c.device, &allocate, &cmd), VK_SUCCESS);
        begin();
    }
    ~EngineCommands() { vkDestroyCommandPool(c_.device, pool_, nullptr); }
    EngineCommands(const EngineCommands&) = delete;
    EngineCommands& operator=(const EngineCommands&) = delete;

    void begin() {
        VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        vkBeginCommandBuffer(cmd, &info);
    }
    // Ends, submits signalling `done`, waits, and begins again.
    void submit(const probe::gpu::Completion& done) {
        vkEndCommandBuffer(cmd);
        submitAndWait(c_.queue, cmd, done);
        begin();
    }

    VkCommandBuffer cmd = VK_NULL_HANDLE;

private:
    const Caller& c_;
    VkCommandPool pool_ = VK_NULL_HANDLE;
};

} // namespace probetest
