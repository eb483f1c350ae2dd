// The conversion pass (shaders/convert_b10g11r11.comp) for a B10G11R11 output on a device that
// cannot store that format: per output level computed, pass 2's RGBA32F mip packed into R32_UINT
// words, then copied into the output cube (the formats are size-compatible).
#include <cstdint>

#include <convert_b10g11r11.spv.h>

#include "filter_impl.h"

namespace probe::gpu {

namespace {

struct ConvertConstants {
    int32_t size;
};

} // namespace

std::unique_ptr<ComputePipeline> makeConvertPipeline(const Filter::Impl& impl) { return impl.pipeline(kConvertB10g11r11Spv); }

void recordConversion(Filter::Impl& impl, VkCommandBuffer commandBuffer, VkImage output, const std::vector<int>& levels) {
    impl.barrier(commandBuffer);
    std::vector<VkImageCopy> copies;
    for (int m : levels) {
        const int size = impl.settings.faceSize >> m;
        impl.descriptors->bind(commandBuffer, impl.current->convertSets[m]);
        dispatchPass(impl, commandBuffer, *impl.convert, "convert", m, ConvertConstants{size},
                     groupsFor(texelCount(size) * std::size_t(impl.settings.batchSize)));
        VkImageCopy copy{};
        copy.srcSubresource = copy.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), 0, impl.current->packed.layers()};
        copy.extent = {uint32_t(size), uint32_t(size), 1};
        copies.push_back(copy);
    }
    const auto mips = uint32_t(impl.current->packed.mips());
    imageBarrier(commandBuffer, impl.current->packed.handle(), 0, mips, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_TRANSFER_READ_BIT);
    vkCmdCopyImage(commandBuffer, impl.current->packed.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, output,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, uint32_t(copies.size()), copies.data());
    imageBarrier(commandBuffer, impl.current->packed.handle(), 0, mips, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                 VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                 VK_ACCESS_SHADER_WRITE_BIT);
}

} // namespace probe::gpu
