// Decodes a BC6H KTX2 cube as a GPU samples it: the levels' blocks uploaded into a
// VK_FORMAT_BC6H_UFLOAT_BLOCK image, every texel read with texelFetch by tests/bc6h_sample.comp,
// written as float32 RGB, level after level, the faces, each row-major. bench/scripts/bc6h.py
// --sampled compares them with bcdec's decode of the same blocks.
// Usage: bc6h_sample IN.ktx2 OUT.raw [DEVICE]
#include <array>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <bc6h_sample.spv.h>
#include <fmt/format.h>

#include "buffer.h"
#include "compute_pipeline.h"
#include "device.h"
#include "image.h"
#include "probe/ktx2.h"
#include "submission.h"
#include "vulkan_check.h"

using namespace probe::gpu;

namespace {

constexpr VkFormat kBc6h = VK_FORMAT_BC6H_UFLOAT_BLOCK;

// One storage buffer (binding 0) and one sampled image (binding 1).
struct SampleLayout {
    VkDevice device;
    VkDescriptorSetLayout set = VK_NULL_HANDLE;
    VkPipelineLayout pipeline = VK_NULL_HANDLE;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VkDescriptorSet descriptors = VK_NULL_HANDLE;

    explicit SampleLayout(VkDevice d) : device(d) {
        const std::array<VkDescriptorSetLayoutBinding, 2> bindings{
            {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
             {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}}};
        VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        setInfo.bindingCount = 2;
        setInfo.pBindings = bindings.data();
        vkCheck(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &set), "vkCreateDescriptorSetLayout");
        const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, kPushConstantBytes};
        VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        layoutInfo.setLayoutCount = 1;
        layoutInfo.pSetLayouts = &set;
        layoutInfo.pushConstantRangeCount = 1;
        layoutInfo.pPushConstantRanges = &range;
        vkCheck(vkCreatePipelineLayout(device, &layoutInfo, nullptr, &pipeline), "vkCreatePipelineLayout");
        const std::array<VkDescriptorPoolSize, 2> sizes{
            {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1}, {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1}}};
        VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        poolInfo.maxSets = 1;
        poolInfo.poolSizeCount = 2;
        poolInfo.pPoolSizes = sizes.data();
        vkCheck(vkCreateDescriptorPool(device, &poolInfo, nullptr, &pool), "vkCreateDescriptorPool");
        VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO, nullptr, pool, 1, &set};
        vkCheck(vkAllocateDescriptorSets(device, &allocate, &descriptors), "vkAllocateDescriptorSets");
    }
    ~SampleLayout() {
        vkDestroyDescriptorPool(device, pool, nullptr);
        vkDestroyPipelineLayout(device, pipeline, nullptr);
        vkDestroyDescriptorSetLayout(device, set, nullptr);
    }
    SampleLayout(const SampleLayout&) = delete;
    SampleLayout& operator=(const SampleLayout&) = delete;
};

} // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: bc6h_sample IN.ktx2 OUT.raw [DEVICE]\n");
        return 2;
    }
    try {
        const probe::Ktx2Levels k = probe::readKtx2Levels(argv[1]);
        if (k.format != probe::Ktx2PixelFormat::bc6h) throw std::runtime_error(fmt::format("{}: not a BC6H cube", argv[1]));
        DeviceOptions options;
        options.validation = true;
        if (argc > 3) options.choice = argv[3];
        const Device device(options);
        if ((device.impl().features(kBc6h) & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT) == 0)
            throw std::runtime_error(fmt::format("{} cannot sample BC6H images", device.info().name));
        const auto levelCount = int(k.levels.size());
        const CubeImageResource image(device, k.faceSize, levelCount, kBc6h, VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
        const ImageView view(device.device(), image.handle(), kBc6h, VK_IMAGE_VIEW_TYPE_2D_ARRAY, 0, uint32_t(levelCount));
        const Sampler nearest(device.device(), false);
        std::size_t blockBytes = 0, texelTotal = 0;
        for (int m = 0; m < levelCount; ++m) {
            blockBytes += k.levels[m].size();
            texelTotal += probe::texelCount(std::max(k.faceSize >> m, 1));
        }
        Buffer staging(device, std::max(blockBytes, texelTotal * 16), Buffer::Kind::staging);
        Buffer texels(device, texelTotal * 16, Buffer::Kind::storage);
        std::vector<VkBufferImageCopy> regions;
        VkDeviceSize offset = 0;
        for (int m = 0; m < levelCount; ++m) {
            std::memcpy(static_cast<uint8_t*>(staging.mapped()) + offset, k.levels[m].data(), k.levels[m].size());
            VkBufferImageCopy region{};
            region.bufferOffset = offset;
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), 0, 6};
            const auto size = uint32_t(std::max(k.faceSize >> m, 1));
            region.imageExtent = {size, size, 1};
            regions.push_back(region);
            offset += k.levels[m].size();
        }

        const SampleLayout layout(device.device());
        const VkDescriptorBufferInfo bufferInfo{texels.handle(), 0, VK_WHOLE_SIZE};
        const VkDescriptorImageInfo imageInfo{nearest.handle(), view.handle(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        std::array<VkWriteDescriptorSet, 2> writes{};
        for (VkWriteDescriptorSet& w : writes) {
            w.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
            w.dstSet = layout.descriptors;
            w.descriptorCount = 1;
        }
        writes[0].dstBinding = 0;
        writes[0].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        writes[0].pBufferInfo = &bufferInfo;
        writes[1].dstBinding = 1;
        writes[1].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        writes[1].pImageInfo = &imageInfo;
        vkUpdateDescriptorSets(device.device(), 2, writes.data(), 0, nullptr);
        const ComputePipeline pipeline(device.device(), layout.pipeline, kBc6hSampleSpv);

        Submission submission(device);
        VkCommandBuffer cmd = submission.begin();
        imageBarrier(cmd, image.handle(), 0, uint32_t(levelCount), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
        vkCmdCopyBufferToImage(cmd, staging.handle(), image.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, uint32_t(regions.size()),
                               regions.data());
        imageBarrier(cmd, image.handle(), 0, uint32_t(levelCount), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.pipeline, 0, 1, &layout.descriptors, 0, nullptr);
        const std::array<int32_t, 3> constants{k.faceSize, levelCount, int32_t(texelTotal)};
        pipeline.dispatch(cmd, std::as_bytes(std::span(constants)), groupsFor(texelTotal));
        computeBarrier(cmd);
        const VkBufferCopy back{0, 0, texelTotal * 16};
        vkCmdCopyBuffer(cmd, texels.handle(), staging.handle(), 1, &back);
        hostReadBarrier(cmd);
        submission.submitAndWait(cmd);
        submission.release(cmd);
        if (!device.validationMessages().empty()) throw std::runtime_error("validation: " + device.validationMessages().front());

        std::ofstream out(argv[2], std::ios::binary);
        const auto* rgba = static_cast<const float*>(staging.mapped());
        for (std::size_t t = 0; t < texelTotal; ++t) out.write(reinterpret_cast<const char*>(rgba + 4 * t), 3 * sizeof(float));
        std::printf("bc6h_sample: %zu texels of %s decoded by %s\n", texelTotal, argv[1], device.info().name.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bc6h_sample: %s\n", e.what());
        return 1;
    }
    return 0;
}
