#include "separate_cubes.h"

#include <fmt/format.h>

#include "device.h"
#include "image.h"
#include "probe/error.h"

namespace probe::gpu {

namespace {

void pipelineBarrier(VkCommandBuffer commandBuffer, const std::vector<VkImageMemoryBarrier>& images) {
    const VkPipelineStageFlags stages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    vkCmdPipelineBarrier(commandBuffer, stages, stages, 0, 0, nullptr, 0, nullptr, uint32_t(images.size()), images.data());
}

// A whole cube: mip `mip`, `layers` layers from `first`.
VkImageSubresourceLayers cubeLayers(uint32_t mip, uint32_t first) { return {VK_IMAGE_ASPECT_COLOR_BIT, mip, first, kFaceCount}; }

} // namespace

void checkSeparateCubes(const Filter::Impl& f, VkCommandBuffer commandBuffer, const std::vector<SourceCube>& sources,
                        const std::vector<OutputCube>& outputs) {
    const auto refuse = [](const std::string& field, const std::string& problem) {
        return ProbeError(fmt::format("Filter::record: {} {}", field, problem));
    };
    const auto batch = std::size_t(f.settings.batchSize);
    const uint32_t faceSize = uint32_t(f.settings.faceSize), levelCount = uint32_t(f.settings.levelCount);
    if (commandBuffer == VK_NULL_HANDLE) throw refuse("commandBuffer", "is VK_NULL_HANDLE");
    if (sources.size() != batch)
        throw refuse("sources", fmt::format("holds {} cubes, but the filter's batchSize is {}", sources.size(), batch));
    if (outputs.size() != batch)
        throw refuse("outputs", fmt::format("holds {} cubes, but the filter's batchSize is {}", outputs.size(), batch));
    for (std::size_t p = 0; p < batch; ++p) {
        const SourceCube& s = sources[p];
        const std::string name = fmt::format("sources[{}]", p);
        if (s.image == VK_NULL_HANDLE) throw refuse(name + ".image", "is VK_NULL_HANDLE: a batch of separate cubes copies each source");
        if (!(s.usage & VK_IMAGE_USAGE_TRANSFER_SRC_BIT)) throw refuse(name + ".usage", "lacks TRANSFER_SRC, which its copy reads it with");
        if (s.faceSize != faceSize)
            throw refuse(name + ".faceSize", fmt::format("is {}, but the filter was built for S_0 = {}", s.faceSize, faceSize));
        if (s.arrayLayers != kFaceCount)
            throw refuse(name + ".arrayLayers", fmt::format("is {}, but a cube of a batch of separate cubes has 6", s.arrayLayers));
        if (s.format != sources.front().format)
            throw refuse(name + ".format", fmt::format("is {}, but sources[0].format is {}: one array holds them", int(s.format),
                                                       int(sources.front().format)));
        if (!(f.device.impl().features(s.format) & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT))
            throw refuse(name + ".format", fmt::format("{} cannot be sampled on {}", int(s.format), f.device.info().name));
    }
    for (std::size_t p = 0; p < batch; ++p) {
        const OutputCube& o = outputs[p];
        const std::string name = fmt::format("outputs[{}]", p);
        if (o.image == VK_NULL_HANDLE) throw refuse(name + ".image", "is VK_NULL_HANDLE");
        if (o.format != f.settings.outputFormat)
            throw refuse(name + ".format",
                         fmt::format("is {}, but the filter was built for {}", formatName(o.format), formatName(f.settings.outputFormat)));
        if (o.faceSize != faceSize)
            throw refuse(name + ".faceSize", fmt::format("is {}, but the filter was built for S_0 = {}", o.faceSize, faceSize));
        if (o.mipLevels < levelCount)
            throw refuse(name + ".mipLevels", fmt::format("is {}, but the filter writes {} levels", o.mipLevels, levelCount));
        if (o.arrayLayers != kFaceCount)
            throw refuse(name + ".arrayLayers", fmt::format("is {}, but a cube of a batch of separate cubes has 6", o.arrayLayers));
        if (!(o.usage & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
            throw refuse(name + ".usage", "lacks TRANSFER_DST, which its copy writes it with");
    }
}

void makeSeparateCubeImages(Filter::Impl& f, VkFormat format) {
    Recording& r = *f.current;
    f.makeOwnOutput(r);
    if (r.copySource.handle() && r.copySource.format() == format) return;
    r.copySourceView = {};
    r.copySource = CubeImageResource(f.device, f.settings.faceSize, 1, format, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                     f.settings.batchSize);
    r.copySourceView = ImageView(f.device.device(), r.copySource.handle(), format, f.cubeViewType(), 0, 1, r.copySource.layers());
}

void copySourcesIn(Filter::Impl& f, VkCommandBuffer commandBuffer, const std::vector<SourceCube>& sources) {
    const Recording& r = *f.current;
    // The sources from the engine's layout to the copy's; the array from whatever an earlier recording
    // left (its reads ended at the compute stage).
    std::vector<VkImageMemoryBarrier> before{imageMemoryBarrier(r.copySource.handle(), 0, 1, r.copySource.layers(),
                                                                VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                                                                VK_ACCESS_TRANSFER_WRITE_BIT)};
    for (const SourceCube& s : sources)
        before.push_back(imageMemoryBarrier(s.image, 0, 1, kFaceCount, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                            VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 0, VK_ACCESS_TRANSFER_READ_BIT));
    pipelineBarrier(commandBuffer, before);
    for (std::size_t p = 0; p < sources.size(); ++p) {
        VkImageCopy cube{};
        cube.srcSubresource = cubeLayers(0, 0);
        cube.dstSubresource = cubeLayers(0, uint32_t(kFaceCount * p));
        cube.extent = {uint32_t(f.settings.faceSize), uint32_t(f.settings.faceSize), 1};
        vkCmdCopyImage(commandBuffer, sources[p].image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, r.copySource.handle(),
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &cube);
    }
    // The array for the passes' reads, the sources back in the engine's layout, the set's output
    // writable by the passes.
    std::vector<VkImageMemoryBarrier> after{
        imageMemoryBarrier(r.copySource.handle(), 0, 1, r.copySource.layers(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                           VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT),
        imageMemoryBarrier(r.runOutput.handle(), 0, uint32_t(f.settings.levelCount), r.runOutput.layers(), VK_IMAGE_LAYOUT_UNDEFINED,
                           f.ownOutputLayout(), 0, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT)};
    for (const SourceCube& s : sources)
        after.push_back(imageMemoryBarrier(s.image, 0, 1, kFaceCount, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                           VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_READ_BIT,
                                           VK_ACCESS_SHADER_READ_BIT));
    pipelineBarrier(commandBuffer, after);
}

void copyOutputsOut(Filter::Impl& f, VkCommandBuffer commandBuffer, const std::vector<OutputCube>& outputs) {
    const Recording& r = *f.current;
    // The set's output from the passes' writes to the copies' reads (the outputs' earlier use ended at
    // the transfer stage: record()'s contract).
    pipelineBarrier(commandBuffer,
                    {imageMemoryBarrier(r.runOutput.handle(), 0, uint32_t(f.settings.levelCount), r.runOutput.layers(), f.ownOutputLayout(),
                                        VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                                        VK_ACCESS_TRANSFER_READ_BIT)});
    for (std::size_t p = 0; p < outputs.size(); ++p) {
        std::vector<VkImageCopy> levels;
        for (int m : f.plan.computedLevels) {
            VkImageCopy level{};
            level.srcSubresource = cubeLayers(uint32_t(m), uint32_t(kFaceCount * p));
            level.dstSubresource = cubeLayers(uint32_t(m), 0);
            level.extent = {uint32_t(f.settings.faceSize >> m), uint32_t(f.settings.faceSize >> m), 1};
            levels.push_back(level);
        }
        vkCmdCopyImage(commandBuffer, r.runOutput.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, outputs[p].image,
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, uint32_t(levels.size()), levels.data());
    }
}

} // namespace probe::gpu
