// The Filter's descriptor sets: shaders/buffers.glsl's bindings 0-4 and 9 and shaders/images.glsl's
// 5-8 and 10 in one set layout, one pipeline layout (with kPushConstantBytes of push constants), and
// sets from one pool, each written with the resources of the dispatches that bind it.
#pragma once

#include <bit>
#include <cstdint>

#include <vulkan/vulkan.h>

#include "probe/shared_constants.h"

namespace probe::gpu {

enum FilterBinding : uint32_t {
    kPyramidBuffer = 0,    // storage buffer: the bordered pyramid (exact sampling; the reference's source)
    kAccumulator = 1,      // storage buffer: the reference's running sums
    kGeometry = 2,         // storage buffer: texel directions and solid angles per level
    kTableTexels = 3,      // uniform texel buffer: the tap table or FIS samples
    kPyramidTexels = 4,    // uniform texel buffer: the bordered pyramid, read
    kSourceCube = 5,       // combined image sampler: the source cube, nearest
    kPyramidCube = 6,      // combined image sampler: the pyramid cube, trilinear (the conversion pass's input)
    kPyramidMip = 7,       // storage image: the pyramid mip written (hardware sampling)
    kOutputMip = 8,        // storage image: the output mip written (the conversion pass's packed words)
    kTableBuffer = 9,      // storage buffer: the tap table or FIS samples again (hardware sampling)
    kPyramidTailMips = 10, // storage images (kPyramidTailMipCount): the mips of pass 1's last dispatch
    kFilterBindingCount = 11,
};

// The mips of face size PROBE_PYRAMID_TAIL_SIZE down to 1 (pyramid_tail.comp).
inline constexpr int kPyramidTailMipCount = std::bit_width(unsigned(PROBE_PYRAMID_TAIL_SIZE));

class FilterDescriptors {
public:
    FilterDescriptors(VkDevice device, uint32_t maxSets);
    ~FilterDescriptors();
    FilterDescriptors(const FilterDescriptors&) = delete;
    FilterDescriptors& operator=(const FilterDescriptors&) = delete;

    VkPipelineLayout pipelineLayout() const { return pipelineLayout_; }
    // A set from the pool (at most maxSets until reset()); write the bindings its dispatches read.
    VkDescriptorSet allocate();
    // Returns every set to the pool.
    void reset();

    void writeBuffer(VkDescriptorSet set, FilterBinding binding, VkBuffer buffer) const;
    void writeTexelBuffer(VkDescriptorSet set, FilterBinding binding, VkBufferView view) const;
    void writeSampled(VkDescriptorSet set, FilterBinding binding, VkImageView view, VkSampler sampler, VkImageLayout layout) const;
    // VK_IMAGE_LAYOUT_GENERAL, at array element `element` of the binding.
    void writeStorage(VkDescriptorSet set, FilterBinding binding, VkImageView view, uint32_t element = 0) const;
    void bind(VkCommandBuffer commandBuffer, VkDescriptorSet set) const;

private:
    void writeImage(VkDescriptorSet set, FilterBinding binding, uint32_t element, const VkDescriptorImageInfo& info) const;

    VkDevice device_;
    VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
    VkPipelineLayout pipelineLayout_ = VK_NULL_HANDLE;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
};

} // namespace probe::gpu
