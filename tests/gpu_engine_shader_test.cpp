// The drop-in engine shader (shaders/engine/probe_table_filter.glsl) in a pipeline of its own, as an
// engine builds it: its two bindings, its push constant, its (S / 8, S / 8, 6) dispatch per level
// with no barrier between levels. Compiled with the default table (gltf128_quad8) and with a
// constant one (gltf128_const8), it reads the table's pyramid (the CPU model's, uploaded into an
// RGBA32F cube with every mip) through a seamless trilinear sampler and gives the CPU model's levels,
// within the hardware sampling tolerance of gpu_test_support.h.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>

#include <engine_gltf128_const8.spv.h>
#include <engine_gltf128_quad8.spv.h>
#include <fmt/format.h>

#include "buffer.h"
#include "gpu_test_support.h"
#include "image.h"
#include "probe/table_filter.h"
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

    DropInPipeline(VkDevice d, std::span<const uint32_t> spirv, uint32_t maxSets) : device(d) {
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
        moduleInfo.codeSize = spirv.size_bytes();
        moduleInfo.pCode = spirv.data();
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
    DropInPipeline(const DropInPipeline&) = delete;
    DropInPipeline& operator=(const DropInPipeline&) = delete;

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

// Regions of a buffer that holds `mips` levels of RGBA32F texels one after another, from face size `size`.
std::vector<VkBufferImageCopy> levelRegions(int size, int mips) {
    std::vector<VkBufferImageCopy> regions;
    VkDeviceSize offset = 0;
    for (int m = 0; m < mips; ++m) {
        VkBufferImageCopy region{};
        region.bufferOffset = offset;
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), 0, 6};
        region.imageExtent = {uint32_t(size >> m), uint32_t(size >> m), 1};
        regions.push_back(region);
        offset += texelCount(size >> m) * 4 * sizeof(float);
    }
    return regions;
}

// Levels 1 .. levelCount - 1 of `table` on `source`, by the drop-in compiled with that table.
CubeLevels runDropIn(const TapTable& table, std::span<const uint32_t> spirv, const CubeLevels& pyramid) {
    const gpu::Device& device = probetest::testDevice();
    const int size = table.baseSize, levels = table.levelCount, mips = int(pyramid.size());
    const VkFormat format = VK_FORMAT_R32G32B32A32_SFLOAT;
    const gpu::CubeImageResource pyramidImage(device, size, mips, format, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
    const gpu::CubeImageResource outputImage(device, size, levels, format, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    const std::vector<VkBufferImageCopy> pyramidRegions = levelRegions(size, mips), outputRegions = levelRegions(size, levels);
    std::vector<float> texels;
    for (const CubeImage& mip : pyramid)
        for (std::size_t t = 0; t < texelCount(mip.size); ++t)
            texels.insert(texels.end(), {mip.rgb[3 * t], mip.rgb[3 * t + 1], mip.rgb[3 * t + 2], 1.0f});
    gpu::Buffer staging(device, texels.size() * sizeof(float), gpu::Buffer::Kind::staging);
    std::memcpy(staging.mapped(), texels.data(), texels.size() * sizeof(float));
    const VkBufferImageCopy& last = outputRegions.back();
    gpu::Buffer readBack(device, last.bufferOffset + texelCount(size >> (levels - 1)) * 4 * sizeof(float), gpu::Buffer::Kind::staging);

    const gpu::ImageView pyramidView(device.device(), pyramidImage.handle(), format, VK_IMAGE_VIEW_TYPE_CUBE, 0, uint32_t(mips));
    const gpu::Sampler sampler(device.device(), true);
    std::vector<gpu::ImageView> outputViews;
    for (int m = 0; m < levels; ++m)
        outputViews.emplace_back(device.device(), outputImage.handle(), format, VK_IMAGE_VIEW_TYPE_2D_ARRAY, uint32_t(m), 1u);
    const DropInPipeline dropIn(device.device(), spirv, uint32_t(levels));

    gpu::Submission submission(device);
    VkCommandBuffer cmd = submission.begin();
    gpu::imageBarrier(cmd, pyramidImage.handle(), 0, uint32_t(mips), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    vkCmdCopyBufferToImage(cmd, staging.handle(), pyramidImage.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                           uint32_t(pyramidRegions.size()), pyramidRegions.data());
    gpu::imageBarrier(cmd, pyramidImage.handle(), 0, uint32_t(mips), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    gpu::imageBarrier(cmd, outputImage.handle(), 0, uint32_t(levels), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, dropIn.pipeline);
    for (int m = 1; m < levels; ++m) { // level 0 is a copy of the source, not the shader's
        const VkDescriptorSet set = dropIn.set(pyramidView.handle(), sampler.handle(), outputViews[m].handle());
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, dropIn.layout, 0, 1, &set, 0, nullptr);
        const int32_t level = m;
        vkCmdPushConstants(cmd, dropIn.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(level), &level);
        const uint32_t groups = uint32_t((size >> m) + 7) / 8;
        vkCmdDispatch(cmd, groups, groups, 6);
    }
    gpu::imageBarrier(cmd, outputImage.handle(), 0, uint32_t(levels), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_ACCESS_TRANSFER_READ_BIT);
    vkCmdCopyImageToBuffer(cmd, outputImage.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readBack.handle(), uint32_t(levels - 1),
                           outputRegions.data() + 1);
    submission.submitAndWait(cmd);
    submission.release(cmd);

    CubeLevels result;
    const auto* data = static_cast<const std::byte*>(readBack.mapped());
    for (int m = 0; m < levels; ++m) {
        CubeImage level(size >> m);
        level.rgb.clear();
        if (m > 0) gpu::unpackTexels(data + outputRegions[m].bufferOffset, texelCount(size >> m), format, level.rgb);
        result.push_back(std::move(level));
    }
    return result;
}

void expectDropInEqualsModel(const std::string& tableName, std::span<const uint32_t> spirv) {
    const TapTable table = readTable(std::filesystem::path(PROBE_TEST_TABLES) / (tableName + ".json"));
    const CubeLevels pyramid = buildPyramid(probetest::randomProbe(table.baseSize, 31), table.pyramid);
    const CubeLevels expected = tableFilter(pyramid, table);
    const CubeLevels levels = runDropIn(table, spirv, pyramid);
    const double tolerance = probetest::kSamplingCases[1].tolerance; // hardware sampling
    for (int m = 1; m < table.levelCount; ++m) {
        const double error = probetest::maxRelativeError(levels[m], expected[m]);
        ::testing::Test::RecordProperty(fmt::format("{} level {}", tableName, m), fmt::format("{:.3g}", error));
        EXPECT_LT(error, tolerance) << tableName << ", level " << m;
    }
}

TEST_F(GpuTest, EngineDropInShaderWithTheDefaultTableEqualsCpuModel) {
    expectDropInEqualsModel("gltf128_quad8", kEngineGltf128Quad8Spv);
}

TEST_F(GpuTest, EngineDropInShaderWithAConstantTableEqualsCpuModel) {
    expectDropInEqualsModel("gltf128_const8", kEngineGltf128Const8Spv);
}

} // namespace
