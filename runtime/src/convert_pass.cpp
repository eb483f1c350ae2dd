// The conversion pass (shaders/convert_b10g11r11.comp) for a B10G11R11 output on a device that
// cannot store that format: per output level computed, pass 2's RGBA32F mip packed into R32_UINT
// words, then copied into the output cube (the formats are size-compatible).
#include <cstdint>

#include <convert_b10g11r11.spv.h>

#include "filter_passes.h"
#include "recording.h"

namespace probe::gpu {

namespace {

struct ConvertConstants {
    int32_t size;
};

} // namespace

ConvertPass::ConvertPass(const PassContext& context) : context_(context), pipeline_(context.pipeline(kConvertB10g11r11Spv)) {}

void ConvertPass::record(const PassRecorder& recorder, const Recording& recording, VkImage output, const std::vector<int>& levels) const {
    const VkCommandBuffer commandBuffer = recorder.commandBuffer;
    recorder.barrier();
    std::vector<VkImageCopy> copies;
    for (int m : levels) {
        const int size = context_.settings.faceSize >> m;
        recorder.bind(recording.convertSets[m]);
        recorder.dispatch(*pipeline_, "convert", m, ConvertConstants{size},
                          groupsFor(texelCount(size) * std::size_t(context_.settings.batchSize)));
        VkImageCopy copy{};
        copy.srcSubresource = copy.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), 0, recording.packed.layers()};
        copy.extent = {uint32_t(size), uint32_t(size), 1};
        copies.push_back(copy);
    }
    const auto mips = uint32_t(recording.packed.mips());
    imageBarrier(commandBuffer, recording.packed.handle(), 0, mips, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_TRANSFER_READ_BIT);
    vkCmdCopyImage(commandBuffer, recording.packed.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, output,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, uint32_t(copies.size()), copies.data());
    imageBarrier(commandBuffer, recording.packed.handle(), 0, mips, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                 VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                 VK_ACCESS_SHADER_WRITE_BIT);
}

} // namespace probe::gpu
