// The drop-in engine shader (shaders/engine/probe_table_filter.glsl, compiled with the committed
// gltf16_quad8 table) in a pipeline of its own, as an engine builds it: its two bindings, its push
// constant, its 8x8x6 dispatch. Fed the pyramid that the runtime's hardware sampling built, it gives
// the runtime's levels: the same taps through the same sampler, to float rounding of the texel
// direction (the drop-in computes it from the face coordinates, the runtime reads it from its
// geometry buffer).
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <engine_table_filter_gltf16_quad8.spv.h>
#include <fmt/format.h>

#include "buffer.h"
#include "gpu_test_support.h"
#include "image.h"
#include "probe/synthetic.h"
#include "probe/table_io.h"
#include "submission.h"
#include "vulkan_check.h"

using namespace probe;
using probetest::GpuTest;

namespace {

// The engine's side: a set layout of the drop-in's two bindings, a pipeline, and one set per level.
struct DropInPipeline {
    VkDevice device;
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkDescriptorPool pool = VK_NULL_HANDLE;

    DropInPipeline(VkDevice d, uint32_t maxSets) : device(d) {
        const std::array<VkDescriptorSetLayoutBinding, 2> bindings{{
            {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
            {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        }};
        VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        setInfo.bindingCount = uint32_t(bindings.size());
        setInfo.pBindings = bindings.data();
        gpu::vkCheck(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &setLayout), "vkCreateDescriptorSetLayout");
        const VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(int32_t)};
        VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        layoutInfo.setLayoutCount = 1;
        layoutInfo.pSetLayouts = &setLayout;
        layoutInfo.pushConstantRangeCount = 1;
        layoutInfo.pPushConstantRanges = &push;
        gpu::vkCheck(vkCreatePipelineLayout(device, &layoutInfo, nullptr, &layout), "vkCreatePipelineLayout");
        VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        moduleInfo.codeSize = sizeof(kEngineTableFilterGltf16Quad8Spv);
        moduleInfo.pCode = kEngineTableFilterGltf16Quad8Spv;
        VkShaderModule module;
        gpu::vkCheck(vkCreateShaderModule(device, &moduleInfo, nullptr, &module), "vkCreateShaderModule");
        VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        info.stage = {
            VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_COMPUTE_BIT, module, "main", nullptr};
        info.layout = layout;
        gpu::vkCheck(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline), "vkCreateComputePipelines");
        vkDestroyShaderModule(device, module, nullptr);
        const std::array<VkDescriptorPoolSize, 2> sizes{
            {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, maxSets}, {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, maxSets}}};
        VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        poolInfo.maxSets = maxSets;
        poolInfo.poolSizeCount = uint32_t(sizes.size());
        poolInfo.pPoolSizes = sizes.data();
        gpu::vkCheck(vkCreateDescriptorPool(device, &poolInfo, nullptr, &pool), "vkCreateDescriptorPool");
    }
    ~DropInPipeline() {
        vkDestroyDescriptorPool(device, pool, nullptr);
        vkDestroyPipeline(device, pipeline, nullptr);
        vkDestroyPipelineLayout(device, layout, nullptr);
        vkDestroyDescriptorSetLayout(device, setLayout, nullptr);
    }

    VkDescriptorSet set(VkImageView pyramid, VkSampler sampler, VkImageView output) const {
        VkDescriptorSetAllocateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        info.descriptorPool = pool;
        info.descriptorSetCount = 1;
        info.pSetLayouts = &setLayout;
        VkDescriptorSet s;
        gpu::vkCheck(vkAllocateDescriptorSets(device, &info, &s), "vkAllocateDescriptorSets");
        const VkDescriptorImageInfo pyramidInfo{sampler, pyramid, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        const VkDescriptorImageInfo outputInfo{VK_NULL_HANDLE, output, VK_IMAGE_LAYOUT_GENERAL};
        std::array<VkWriteDescriptorSet, 2> writes{};
        for (uint32_t b = 0; b < 2; ++b) {
            writes[b] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            writes[b].dstSet = s;
            writes[b].dstBinding = b;
            writes[b].descriptorCount = 1;
            writes[b].descriptorType = b == 0 ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER : VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
            writes[b].pImageInfo = b == 0 ? &pyramidInfo : &outputInfo;
        }
        vkUpdateDescriptorSets(device, uint32_t(writes.size()), writes.data(), 0, nullptr);
        return s;
    }
};

TEST_F(GpuTest, EngineDropInShaderEqualsTheRuntime) {
    const TapTable table = readTable(std::filesystem::path(PROBE_TEST_TABLES) / "gltf16_quad8.json");
    const int size = table.baseSize, levels = table.levelCount, mips = int(std::log2(size)) + 1;
    const gpu::Device& device = probetest::testDevice();
    gpu::Filter filter(device, probetest::tableSettings(table, gpu::Sampling::hardware));
    const CubeLevels expected = filter.run(sunSkyProbe(size));
    const CubeLevels pyramid = filter.downloadPyramid();
    ASSERT_EQ(int(pyramid.size()), mips);

    // The engine's pyramid: the runtime's, uploaded into an RGBA32F cube with every mip.
    const VkFormat format = VK_FORMAT_R32G32B32A32_SFLOAT;
    const gpu::CubeImageResource pyramidImage(device, size, mips, format, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
    const gpu::CubeImageResource outputImage(device, size, levels, format, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    std::vector<float> texels;
    std::vector<VkBufferImageCopy> regions;
    for (int k = 0; k < mips; ++k) {
        VkBufferImageCopy region{};
        region.bufferOffset = texels.size() * sizeof(float);
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(k), 0, 6};
        region.imageExtent = {uint32_t(size >> k), uint32_t(size >> k), 1};
        regions.push_back(region);
        for (std::size_t t = 0; t < texelCount(size >> k); ++t)
            texels.insert(texels.end(), {pyramid[k].rgb[3 * t], pyramid[k].rgb[3 * t + 1], pyramid[k].rgb[3 * t + 2], 1.0f});
    }
    gpu::Buffer staging(device, texels.size() * sizeof(float), gpu::Buffer::Kind::staging);
    std::memcpy(staging.mapped(), texels.data(), texels.size() * sizeof(float));
    std::size_t outputTexels = 0;
    for (int m = 0; m < levels; ++m) outputTexels += texelCount(size >> m);
    gpu::Buffer readBack(device, outputTexels * 4 * sizeof(float), gpu::Buffer::Kind::staging);

    const gpu::ImageView pyramidView(device.device(), pyramidImage.handle(), format, VK_IMAGE_VIEW_TYPE_CUBE, 0, uint32_t(mips));
    const gpu::Sampler sampler(device.device(), true);
    std::vector<gpu::ImageView> outputViews;
    for (int m = 0; m < levels; ++m)
        outputViews.emplace_back(device.device(), outputImage.handle(), format, VK_IMAGE_VIEW_TYPE_2D_ARRAY, uint32_t(m), 1u);
    const DropInPipeline dropIn(device.device(), uint32_t(levels));

    gpu::Submission submission(device);
    VkCommandBuffer cmd = submission.begin();
    gpu::imageBarrier(cmd, pyramidImage.handle(), 0, uint32_t(mips), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    vkCmdCopyBufferToImage(cmd, staging.handle(), pyramidImage.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, uint32_t(regions.size()),
                           regions.data());
    gpu::imageBarrier(cmd, pyramidImage.handle(), 0, uint32_t(mips), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    gpu::imageBarrier(cmd, outputImage.handle(), 0, uint32_t(levels), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, dropIn.pipeline);
    for (int m = 1; m < levels; ++m) { // level 0 is a copy, not the shader's
        const VkDescriptorSet set = dropIn.set(pyramidView.handle(), sampler.handle(), outputViews[m].handle());
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, dropIn.layout, 0, 1, &set, 0, nullptr);
        const int32_t level = m;
        vkCmdPushConstants(cmd, dropIn.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(level), &level);
        const uint32_t groups = uint32_t(std::max((size >> m) / 8, 1));
        vkCmdDispatch(cmd, groups, groups, 6);
    }
    gpu::imageBarrier(cmd, outputImage.handle(), 0, uint32_t(levels), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_ACCESS_TRANSFER_READ_BIT);
    std::vector<VkBufferImageCopy> back;
    VkDeviceSize offset = 0;
    for (int m = 0; m < levels; ++m) {
        VkBufferImageCopy region{};
        region.bufferOffset = offset;
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), 0, 6};
        region.imageExtent = {uint32_t(size >> m), uint32_t(size >> m), 1};
        back.push_back(region);
        offset += texelCount(size >> m) * 4 * sizeof(float);
    }
    vkCmdCopyImageToBuffer(cmd, outputImage.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readBack.handle(), uint32_t(back.size()),
                           back.data());
    submission.submitAndWait(cmd);
    submission.release(cmd);

    const auto* data = static_cast<const std::byte*>(readBack.mapped());
    for (int m = 1; m < levels; ++m) {
        CubeImage level(size >> m);
        level.rgb.clear();
        gpu::unpackTexels(data + back[m].bufferOffset, texelCount(size >> m), format, level.rgb);
        const double error = probetest::maxRelativeError(level, expected[m]);
        ::testing::Test::RecordProperty(fmt::format("level{}_max_relative", m), fmt::format("{:.2e}", error));
        EXPECT_LT(error, 1e-4) << "level " << m;
    }
}

} // namespace
