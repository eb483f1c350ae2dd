// The runtime's compute pipelines, with push constants for the per-dispatch values, and the buffer
// layout of shaders/buffers.glsl that the SH projector and the sphere renderer bind as one
// descriptor set (the Filter adds images: filter_descriptors.h). Bindings 0-1 are storage buffers
// (pyramid, output); the buffers that the hot loops only read are bound as uniform texel buffers,
// whose reads SIMD back ends gather without branches (lavapipe runs them about twice as fast as
// storage-buffer reads) and whose size is bounded by an element count rather than the storage-buffer
// range: binding 2 the geometry, binding 3 the table buffer, binding 4 the pyramid buffer again. (The
// Filter also binds the table as a storage buffer, binding 8, for its hardware-sampling pipelines.)
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include <vulkan/vulkan.h>

#include "buffer.h"
#include "probe/shared_constants.h"

namespace probe::gpu {

inline constexpr uint32_t kBufferCount = 4;                      // pyramid, output, geometry, table
inline constexpr uint32_t kPushConstantBytes = 128;              // what every device offers (maxPushConstantsSize)
inline constexpr uint32_t kWorkgroupSize = PROBE_WORKGROUP_SIZE; // local_size_x of every per-texel shader
inline constexpr uint32_t kMaxGroupsX = 65535;                   // per dispatch row
inline constexpr uint32_t kBatchSizeConstant = 15;               // constant_id of shaders/batch.glsl's kBatchSize

// Part of a storage buffer bound at binding 0 or 1: from `offset` (aligned as the device asks),
// `bytes` long, within the device's storage-buffer range.
struct BufferWindow {
    uint32_t binding = 1;
    VkDeviceSize offset = 0;
    VkDeviceSize bytes = 0;
};

// The layout and the one descriptor set that binds the four buffers (RGBA32F texels, 16 bytes
// each): the storage ones from their start, within the device's storage-buffer range, or through
// `window`. Throws ProbeError naming the device's limit when a texel buffer would exceed it.
class PipelineLayout {
public:
    PipelineLayout(const Device& device, const std::array<const Buffer*, kBufferCount>& buffers,
                   std::optional<BufferWindow> window = std::nullopt);
    ~PipelineLayout();
    PipelineLayout(const PipelineLayout&) = delete;
    PipelineLayout& operator=(const PipelineLayout&) = delete;

    VkPipelineLayout handle() const { return layout_; }
    void bind(VkCommandBuffer commandBuffer) const;

private:
    VkDevice device_;
    VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
    VkDescriptorSet set_ = VK_NULL_HANDLE;
    std::array<VkBufferView, 3> texelViews_{}; // bindings 2 to 4
};

// One compute pipeline from embedded SPIR-V; specialization[i] sets the int constant_id i, for the
// choices fixed per pipeline, whose untaken paths the driver then compiles out, and `batchSize` the
// cubes of a batch (kBatchSizeConstant). `flags` and `cache` (the engine's, or none) go to
// vkCreateComputePipelines (bench/shader_stats/shader_stats asks for the driver's statistics).
class ComputePipeline {
public:
    ComputePipeline(VkDevice device, VkPipelineLayout layout, std::span<const uint32_t> spirv, std::span<const int32_t> specialization = {},
                    VkPipelineCreateFlags flags = 0, VkPipelineCache cache = VK_NULL_HANDLE, int32_t batchSize = 1);
    ComputePipeline(VkDevice device, const PipelineLayout& layout, std::span<const uint32_t> spirv,
                    std::span<const int32_t> specialization = {})
        : ComputePipeline(device, layout.handle(), spirv, specialization) {}
    ~ComputePipeline();
    ComputePipeline(const ComputePipeline&) = delete;
    ComputePipeline& operator=(const ComputePipeline&) = delete;

    // Binds the pipeline, pushes `constants` and dispatches `groups` workgroups (split over y beyond
    // kMaxGroupsX) in each of `layers` layers over z.
    void dispatch(VkCommandBuffer commandBuffer, std::span<const std::byte> constants, uint32_t groups, uint32_t layers = 1) const;
    VkPipeline handle() const { return pipeline_; }

private:
    VkDevice device_;
    VkPipelineLayout layout_;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
};

// Workgroups to cover `invocations` threads.
inline uint32_t groupsFor(std::size_t invocations) { return static_cast<uint32_t>((invocations + kWorkgroupSize - 1) / kWorkgroupSize); }

// Makes the shader writes of one dispatch visible to the next dispatch's reads and to transfers.
void computeBarrier(VkCommandBuffer commandBuffer);

} // namespace probe::gpu
