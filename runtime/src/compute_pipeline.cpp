#include "compute_pipeline.h"

#include <algorithm>
#include <vector>

#include <fmt/format.h>

#include "device.h"
#include "probe/error.h"
#include "vulkan_check.h"

namespace probe::gpu {

namespace {

constexpr uint32_t kStorageBindings = 2; // pyramid, output
constexpr uint32_t kBindingCount = 5;    // and the geometry, the table and the pyramid as uniform texel buffers
constexpr VkDeviceSize kTexelBytes = 16; // RGBA32F

} // namespace

PipelineLayout::PipelineLayout(const Device& device, const std::array<const Buffer*, kBufferCount>& buffers,
                               std::optional<BufferWindow> window)
    : device_(device.device()) {
    const Device::Impl& d = device.impl();
    // The geometry (binding 2), the table (binding 3) and the pyramid (binding 4), read as texels.
    const std::array<const Buffer*, 3> texelBuffers{buffers[2], buffers[3], buffers[0]};
    VkFormatProperties properties;
    vkGetPhysicalDeviceFormatProperties(d.physical, VK_FORMAT_R32G32B32A32_SFLOAT, &properties);
    if (!(properties.bufferFeatures & VK_FORMAT_FEATURE_UNIFORM_TEXEL_BUFFER_BIT))
        throw ProbeError(fmt::format("Vulkan: {} cannot read R32G32B32A32_SFLOAT uniform texel buffers", d.info.name));
    for (const Buffer* b : texelBuffers)
        if (b->bytes() / kTexelBytes > d.limits.maxTexelBufferElements)
            throw ProbeError(fmt::format("Vulkan: {} reads texel buffers of at most {} texels, this one has {}; use a smaller --size",
                                         d.info.name, d.limits.maxTexelBufferElements, b->bytes() / kTexelBytes));

    std::array<VkDescriptorSetLayoutBinding, kBindingCount> bindings{};
    for (uint32_t b = 0; b < kBindingCount; ++b) {
        bindings[b].binding = b;
        bindings[b].descriptorType = b < kStorageBindings ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER : VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
        bindings[b].descriptorCount = 1;
        bindings[b].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = kBindingCount;
    setInfo.pBindings = bindings.data();
    vkCheck(vkCreateDescriptorSetLayout(device_, &setInfo, nullptr, &setLayout_), "vkCreateDescriptorSetLayout");

    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, kPushConstantBytes};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.setLayoutCount = 1;
    layoutInfo.pSetLayouts = &setLayout_;
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &range;
    vkCheck(vkCreatePipelineLayout(device_, &layoutInfo, nullptr, &layout_), "vkCreatePipelineLayout");

    const std::array<VkDescriptorPoolSize, 2> poolSizes{{{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kStorageBindings},
                                                         {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, kBindingCount - kStorageBindings}}};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = static_cast<uint32_t>(poolSizes.size());
    poolInfo.pPoolSizes = poolSizes.data();
    vkCheck(vkCreateDescriptorPool(device_, &poolInfo, nullptr, &pool_), "vkCreateDescriptorPool");
    VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    allocate.descriptorPool = pool_;
    allocate.descriptorSetCount = 1;
    allocate.pSetLayouts = &setLayout_;
    vkCheck(vkAllocateDescriptorSets(device_, &allocate, &set_), "vkAllocateDescriptorSets");

    for (std::size_t v = 0; v < texelViews_.size(); ++v) {
        VkBufferViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
        viewInfo.buffer = texelBuffers[v]->handle();
        viewInfo.format = VK_FORMAT_R32G32B32A32_SFLOAT;
        viewInfo.range = VK_WHOLE_SIZE;
        vkCheck(vkCreateBufferView(device_, &viewInfo, nullptr, &texelViews_[v]), "vkCreateBufferView");
    }
    std::array<VkDescriptorBufferInfo, kStorageBindings> infos{};
    std::array<VkWriteDescriptorSet, kBindingCount> writes{};
    for (uint32_t b = 0; b < kBindingCount; ++b) {
        writes[b] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        writes[b].dstSet = set_;
        writes[b].dstBinding = b;
        writes[b].descriptorCount = 1;
        writes[b].descriptorType = bindings[b].descriptorType;
        if (b < kStorageBindings) {
            // Within the storage-buffer range: a pyramid larger than that is only read, as texels.
            infos[b] = {buffers[b]->handle(), 0, std::min<VkDeviceSize>(buffers[b]->bytes(), d.limits.maxStorageBufferRange)};
            if (window && window->binding == b) infos[b] = {buffers[b]->handle(), window->offset, window->bytes};
            writes[b].pBufferInfo = &infos[b];
        } else {
            writes[b].pTexelBufferView = &texelViews_[b - kStorageBindings];
        }
    }
    vkUpdateDescriptorSets(device_, kBindingCount, writes.data(), 0, nullptr);
}

PipelineLayout::~PipelineLayout() {
    for (VkBufferView view : texelViews_)
        if (view) vkDestroyBufferView(device_, view, nullptr);
    vkDestroyDescriptorPool(device_, pool_, nullptr);
    vkDestroyPipelineLayout(device_, layout_, nullptr);
    vkDestroyDescriptorSetLayout(device_, setLayout_, nullptr);
}

void PipelineLayout::bind(VkCommandBuffer commandBuffer) const {
    vkCmdBindDescriptorSets(commandBuffer, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set_, 0, nullptr);
}

ComputePipeline::ComputePipeline(VkDevice device, VkPipelineLayout layout, std::span<const uint32_t> spirv,
                                 std::span<const int32_t> specialization, VkPipelineCreateFlags flags, VkPipelineCache cache,
                                 int32_t batchSize)
    : device_(device), layout_(layout) {
    VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    moduleInfo.codeSize = spirv.size_bytes();
    moduleInfo.pCode = spirv.data();
    VkShaderModule module = VK_NULL_HANDLE;
    vkCheck(vkCreateShaderModule(device_, &moduleInfo, nullptr, &module), "vkCreateShaderModule");
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.flags = flags;
    info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = module;
    info.stage.pName = "main";
    std::vector<int32_t> values(specialization.begin(), specialization.end());
    std::vector<VkSpecializationMapEntry> entries;
    for (uint32_t i = 0; i < values.size(); ++i) entries.push_back({i, i * uint32_t(sizeof(int32_t)), sizeof(int32_t)});
    if (batchSize != 1) {
        entries.push_back({kBatchSizeConstant, uint32_t(values.size() * sizeof(int32_t)), sizeof(int32_t)});
        values.push_back(batchSize);
    }
    const VkSpecializationInfo specializationInfo{static_cast<uint32_t>(entries.size()), entries.data(), values.size() * sizeof(int32_t),
                                                  values.data()};
    if (!values.empty()) info.stage.pSpecializationInfo = &specializationInfo;
    info.layout = layout_;
    const VkResult result = vkCreateComputePipelines(device_, cache, 1, &info, nullptr, &pipeline_);
    vkDestroyShaderModule(device_, module, nullptr);
    vkCheck(result, "vkCreateComputePipelines");
}

ComputePipeline::~ComputePipeline() { vkDestroyPipeline(device_, pipeline_, nullptr); }

void ComputePipeline::dispatch(VkCommandBuffer commandBuffer, std::span<const std::byte> constants, uint32_t groups,
                               uint32_t layers) const {
    vkCmdBindPipeline(commandBuffer, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
    vkCmdPushConstants(commandBuffer, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, static_cast<uint32_t>(constants.size()), constants.data());
    // More than 65535 workgroups (the guaranteed maxComputeWorkGroupCount[0]) go over y; the shaders
    // flatten (x, y) with invocationIndex() and skip the invocations past the end.
    const uint32_t rows = (groups + kMaxGroupsX - 1) / kMaxGroupsX;
    vkCmdDispatch(commandBuffer, rows > 1 ? kMaxGroupsX : groups, rows, layers);
}

void computeBarrier(VkCommandBuffer commandBuffer) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

} // namespace probe::gpu
