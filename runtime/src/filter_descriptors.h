// The Filter's descriptor sets: shaders/buffers.glsl's bindings 0-4 and 8, shaders/images.glsl's 5-7
// and shaders/workgroup_count.glsl's 9 in one set layout, one pipeline layout (with kPushConstantBytes of push constants), and pools
// of sets (one per recording in flight), each set written with the resources of the dispatches that
// bind it.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <memory>
#include <span>

#include <vulkan/vulkan.h>

#include "probe/shared_constants.h"

namespace probe::gpu {

enum FilterBinding : uint32_t {
    kPyramidBuffer = 0,   // storage buffer: a window of the bordered pyramid (exact sampling; the reference's source)
    kAccumulator = 1,     // storage buffer: the reference's running sums
    kGeometry = 2,        // uniform texel buffer: texel directions and solid angles per level
    kTableTexels = 3,     // uniform texel buffer: the tap table or FIS samples
    kPyramidTexels = 4,   // uniform texel buffer: the bordered pyramid, read
    kSourceCube = 5,      // combined image sampler: the source cube, nearest
    kPyramidCube = 6,     // combined image sampler: the pyramid cube, trilinear (the conversion pass's input)
    kWrittenMips = 7,     // storage images (kWrittenMipCount, or kWideWrittenMipCount): the mips a dispatch writes, from element 0
    kTableBuffer = 8,     // storage buffer: the tap table or FIS samples again (hardware sampling)
    kPyramidCounters = 9, // storage buffer: pass 1's workgroups counted per dispatch (pyramid.comp)
    kFilterBindingCount = 10,
};

// The mips of face size PROBE_PYRAMID_TAIL_SIZE down to 1, which pass 1's last dispatch writes
// (pyramid_tail.comp); every other dispatch writes one mip.
inline constexpr int kPyramidTailMipCount = std::bit_width(unsigned(PROBE_PYRAMID_TAIL_SIZE));
inline constexpr uint32_t kWrittenMipCount = kPyramidTailMipCount;
// Where a device offers as many storage images per stage: the mips of every output level, which pass
// 2's level groups then write in one dispatch (FilterPlan::writtenMipCount).
inline constexpr uint32_t kWideWrittenMipCount = PROBE_MAX_GROUP_LEVELS;

struct FilterBindingLayout {
    VkDescriptorType type;
    uint32_t count;
};

// Each binding's type and count. Every pipeline's layout holds them all, so their counts per type
// are what a device must offer per stage; they stay within Vulkan's guaranteed minimums (4 storage
// buffers, 4 storage images), which a test holds them to. A device that offers more storage images
// gets kWideWrittenMipCount of them at kWrittenMips.
inline constexpr std::array<FilterBindingLayout, kFilterBindingCount> kFilterBindings{{
    {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1},
    {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1},
    {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1},
    {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1},
    {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1},
    {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1},
    {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1},
    {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kWrittenMipCount},
    {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1},
    {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1},
}};

// The descriptors of `type` in one set whose kWrittenMips binding holds `writtenMips` images.
constexpr uint32_t filterDescriptorCount(VkDescriptorType type, uint32_t writtenMips = kWrittenMipCount) {
    uint32_t count = 0;
    for (uint32_t b = 0; b < kFilterBindingCount; ++b)
        if (kFilterBindings[b].type == type) count += b == kWrittenMips ? writtenMips : kFilterBindings[b].count;
    return count;
}

// Sets of the Filter's layout from one pool: a recording's, rewritten at each recording.
class DescriptorPool {
public:
    DescriptorPool(VkDevice device, VkDescriptorSetLayout layout, uint32_t maxSets, uint32_t writtenMips);
    ~DescriptorPool();
    DescriptorPool(const DescriptorPool&) = delete;
    DescriptorPool& operator=(const DescriptorPool&) = delete;

    // A set from the pool (at most maxSets until reset()); write the bindings its dispatches read.
    VkDescriptorSet allocate();
    // Returns every set to the pool.
    void reset();

private:
    VkDevice device_;
    VkDescriptorSetLayout layout_;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
};

class FilterDescriptors {
public:
    // writtenMips: the images of the kWrittenMips binding, kWrittenMipCount or kWideWrittenMipCount.
    FilterDescriptors(VkDevice device, uint32_t writtenMips);
    ~FilterDescriptors();
    FilterDescriptors(const FilterDescriptors&) = delete;
    FilterDescriptors& operator=(const FilterDescriptors&) = delete;

    VkPipelineLayout pipelineLayout() const { return pipelineLayout_; }
    std::unique_ptr<DescriptorPool> makePool(uint32_t maxSets) const;

    void writeBuffer(VkDescriptorSet set, FilterBinding binding, VkBuffer buffer, VkDeviceSize offset = 0,
                     VkDeviceSize range = VK_WHOLE_SIZE) const;
    void writeTexelBuffer(VkDescriptorSet set, FilterBinding binding, VkBufferView view) const;
    void writeSampled(VkDescriptorSet set, FilterBinding binding, VkImageView view, VkSampler sampler, VkImageLayout layout) const;
    // kWrittenMips, in VK_IMAGE_LAYOUT_GENERAL: `mips` from element 0, and the last of them in the
    // elements after, so that a shader that declares fewer images, or one of its own type, finds it
    // in each.
    void writeMips(VkDescriptorSet set, std::span<const VkImageView> mips) const;
    void bind(VkCommandBuffer commandBuffer, VkDescriptorSet set) const;

private:
    // The binding's elements from 0, one per info.
    void writeImages(VkDescriptorSet set, FilterBinding binding, std::span<const VkDescriptorImageInfo> infos) const;

    VkDevice device_;
    uint32_t writtenMips_;
    VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
    VkPipelineLayout pipelineLayout_ = VK_NULL_HANDLE;
};

} // namespace probe::gpu
