#include "filter_descriptors.h"

#include <algorithm>
#include <array>

#include "compute_pipeline.h"
#include "vulkan_check.h"

namespace probe::gpu {

DescriptorPool::DescriptorPool(VkDevice device, VkDescriptorSetLayout layout, uint32_t maxSets, uint32_t writtenMips)
    : device_(device), layout_(layout) {
    std::array<VkDescriptorPoolSize, 4> sizes{{{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0},
                                               {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 0},
                                               {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 0},
                                               {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 0}}};
    for (VkDescriptorPoolSize& size : sizes) size.descriptorCount = filterDescriptorCount(size.type, writtenMips) * maxSets;
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = maxSets;
    poolInfo.poolSizeCount = static_cast<uint32_t>(sizes.size());
    poolInfo.pPoolSizes = sizes.data();
    vkCheck(vkCreateDescriptorPool(device_, &poolInfo, nullptr, &pool_), "vkCreateDescriptorPool");
}

DescriptorPool::~DescriptorPool() { vkDestroyDescriptorPool(device_, pool_, nullptr); }

VkDescriptorSet DescriptorPool::allocate() {
    VkDescriptorSetAllocateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    info.descriptorPool = pool_;
    info.descriptorSetCount = 1;
    info.pSetLayouts = &layout_;
    VkDescriptorSet set = VK_NULL_HANDLE;
    vkCheck(vkAllocateDescriptorSets(device_, &info, &set), "vkAllocateDescriptorSets");
    return set;
}

void DescriptorPool::reset() { vkCheck(vkResetDescriptorPool(device_, pool_, 0), "vkResetDescriptorPool"); }

FilterDescriptors::FilterDescriptors(VkDevice device, uint32_t writtenMips) : device_(device), writtenMips_(writtenMips) {
    std::array<VkDescriptorSetLayoutBinding, kFilterBindingCount> bindings{};
    for (uint32_t b = 0; b < kFilterBindingCount; ++b)
        bindings[b] = {b, kFilterBindings[b].type, b == kWrittenMips ? writtenMips : kFilterBindings[b].count, VK_SHADER_STAGE_COMPUTE_BIT,
                       nullptr};
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = kFilterBindingCount;
    setInfo.pBindings = bindings.data();
    vkCheck(vkCreateDescriptorSetLayout(device_, &setInfo, nullptr, &setLayout_), "vkCreateDescriptorSetLayout");

    const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, kPushConstantBytes};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.setLayoutCount = 1;
    layoutInfo.pSetLayouts = &setLayout_;
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &range;
    vkCheck(vkCreatePipelineLayout(device_, &layoutInfo, nullptr, &pipelineLayout_), "vkCreatePipelineLayout");
}

FilterDescriptors::~FilterDescriptors() {
    vkDestroyPipelineLayout(device_, pipelineLayout_, nullptr);
    vkDestroyDescriptorSetLayout(device_, setLayout_, nullptr);
}

std::unique_ptr<DescriptorPool> FilterDescriptors::makePool(uint32_t maxSets) const {
    return std::make_unique<DescriptorPool>(device_, setLayout_, maxSets, writtenMips_);
}

void FilterDescriptors::writeBuffer(VkDescriptorSet set, FilterBinding binding, VkBuffer buffer, VkDeviceSize offset,
                                    VkDeviceSize range) const {
    const VkDescriptorBufferInfo info{buffer, offset, range};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = set;
    write.dstBinding = binding;
    write.descriptorCount = 1;
    write.descriptorType = kFilterBindings[binding].type;
    write.pBufferInfo = &info;
    vkUpdateDescriptorSets(device_, 1, &write, 0, nullptr);
}

void FilterDescriptors::writeTexelBuffer(VkDescriptorSet set, FilterBinding binding, VkBufferView view) const {
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = set;
    write.dstBinding = binding;
    write.descriptorCount = 1;
    write.descriptorType = kFilterBindings[binding].type;
    write.pTexelBufferView = &view;
    vkUpdateDescriptorSets(device_, 1, &write, 0, nullptr);
}

void FilterDescriptors::writeSampled(VkDescriptorSet set, FilterBinding binding, VkImageView view, VkSampler sampler,
                                     VkImageLayout layout) const {
    const VkDescriptorImageInfo info{sampler, view, layout};
    writeImages(set, binding, {&info, 1});
}

void FilterDescriptors::writeMips(VkDescriptorSet set, std::span<const VkImageView> mips) const {
    std::array<VkDescriptorImageInfo, kWideWrittenMipCount> infos{};
    for (uint32_t e = 0; e < writtenMips_; ++e)
        infos[e] = {VK_NULL_HANDLE, mips[std::min<std::size_t>(e, mips.size() - 1)], VK_IMAGE_LAYOUT_GENERAL};
    writeImages(set, kWrittenMips, std::span(infos).first(writtenMips_));
}

void FilterDescriptors::writeImages(VkDescriptorSet set, FilterBinding binding, std::span<const VkDescriptorImageInfo> infos) const {
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = set;
    write.dstBinding = binding;
    write.descriptorCount = static_cast<uint32_t>(infos.size());
    write.descriptorType = kFilterBindings[binding].type;
    write.pImageInfo = infos.data();
    vkUpdateDescriptorSets(device_, 1, &write, 0, nullptr);
}

void FilterDescriptors::bind(VkCommandBuffer commandBuffer, VkDescriptorSet set) const {
    vkCmdBindDescriptorSets(commandBuffer, VK_PIPELINE_BIND_POINT_COMPUTE, pipelineLayout_, 0, 1, &set, 0, nullptr);
}

} // namespace probe::gpu
