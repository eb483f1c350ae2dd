#include "submission.h"

#include <cstring>

#include "vulkan_check.h"

namespace probe::gpu {

Submission::Submission(const Device& device) : device_(device) {
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = device.queueFamily();
    vkCheck(vkCreateCommandPool(device.device(), &poolInfo, nullptr, &pool_), "vkCreateCommandPool");
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    vkCheck(vkCreateFence(device.device(), &fenceInfo, nullptr, &fence_), "vkCreateFence");
}

Submission::~Submission() {
    if (fence_) vkDestroyFence(device_.device(), fence_, nullptr);
    if (pool_) vkDestroyCommandPool(device_.device(), pool_, nullptr);
}

VkCommandBuffer Submission::begin() {
    VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    allocate.commandPool = pool_;
    allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    allocate.commandBufferCount = 1;
    VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
    vkCheck(vkAllocateCommandBuffers(device_.device(), &allocate, &commandBuffer), "vkAllocateCommandBuffers");
    VkCommandBufferBeginInfo beginInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    vkCheck(vkBeginCommandBuffer(commandBuffer, &beginInfo), "vkBeginCommandBuffer");
    return commandBuffer;
}

void Submission::submitAndWait(VkCommandBuffer commandBuffer, bool end) {
    if (end) vkCheck(vkEndCommandBuffer(commandBuffer), "vkEndCommandBuffer");
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &commandBuffer;
    vkCheck(vkResetFences(device_.device(), 1, &fence_), "vkResetFences");
    vkCheck(vkQueueSubmit(device_.queue(), 1, &submit, fence_), "vkQueueSubmit");
    vkCheck(vkWaitForFences(device_.device(), 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
}

void Submission::release(VkCommandBuffer commandBuffer) { vkFreeCommandBuffers(device_.device(), pool_, 1, &commandBuffer); }

void Submission::upload(const Buffer& to, const void* data, VkDeviceSize bytes) {
    Buffer staging(device_, bytes, Buffer::Kind::staging);
    std::memcpy(staging.mapped(), data, bytes);
    VkCommandBuffer commandBuffer = begin();
    const VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(commandBuffer, staging.handle(), to.handle(), 1, &region);
    submitAndWait(commandBuffer);
    release(commandBuffer);
}

void Submission::download(const Buffer& from, void* data, VkDeviceSize bytes) {
    Buffer staging(device_, bytes, Buffer::Kind::staging);
    VkCommandBuffer commandBuffer = begin();
    const VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(commandBuffer, from.handle(), staging.handle(), 1, &region);
    hostReadBarrier(commandBuffer);
    submitAndWait(commandBuffer);
    release(commandBuffer);
    std::memcpy(data, staging.mapped(), bytes);
}

void hostReadBarrier(VkCommandBuffer commandBuffer) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

} // namespace probe::gpu
