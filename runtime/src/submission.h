// One command pool and fence on the device's queue: record a command buffer, submit it and wait,
// and move data between the host and device buffers through a staging buffer.
#pragma once

#include <vulkan/vulkan.h>

#include "buffer.h"

namespace probe::gpu {

class Submission {
public:
    explicit Submission(const Device& device);
    ~Submission();
    Submission(const Submission&) = delete;
    Submission& operator=(const Submission&) = delete;

    // A primary command buffer from the pool, begun.
    VkCommandBuffer begin();
    // Ends `commandBuffer` if `end`, submits it to the device's queue and waits for it.
    void submitAndWait(VkCommandBuffer commandBuffer, bool end = true);
    void release(VkCommandBuffer commandBuffer);

    // Copies `bytes` from the host into `to` (from offset 0), and back.
    void upload(const Buffer& to, const void* data, VkDeviceSize bytes);
    void download(const Buffer& from, void* data, VkDeviceSize bytes);

private:
    const Device& device_;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
};

// Makes the transfer writes recorded before it visible to host reads once the submission's fence
// has signalled: a fence makes the device's writes available to the device alone.
void hostReadBarrier(VkCommandBuffer commandBuffer);

} // namespace probe::gpu
