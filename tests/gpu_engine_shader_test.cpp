// The drop-in engine shaders (shaders/engine/probe_pyramid.glsl and probe_table_filter.glsl) in
// pipelines of their own, as an engine builds them: two bindings each, the filter's push constant, a
// dispatch per mip of the pyramid with a barrier between, then a dispatch per output level with none.
// Compiled with the default table (gltf128_quad8), a constant one (gltf128_const8) and a mixed one
// (levels of 4 and 8 taps), from the source in mip 0 of an RGBA32F cube (and of an RGBA16F one, the
// drop-ins' default format) they build the CPU model's pyramid and give its levels, within the
// hardware sampling tolerance of gpu_test_support.h (every tap a read of a seamless sampler).
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>

#include <engine_gltf128_const8.spv.h>
#include <engine_gltf128_const8_half.spv.h>
#include <engine_gltf128_constmix.spv.h>
#include <engine_gltf128_quad8.spv.h>
#include <engine_pyramid_gltf128_const8.spv.h>
#include <engine_pyramid_gltf128_const8_half.spv.h>
#include <engine_pyramid_gltf128_constmix.spv.h>
#include <engine_pyramid_gltf128_quad8.spv.h>
#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "buffer.h"
#include "gpu_test_support.h"
#include "image.h"
#include "probe/pyramid.h"
#include "probe/shared_constants.h"
#include "probe/table_filter.h"
#include "probe/table_io.h"
#include "submission.h"
#include "vulkan_check.h"

using namespace probe;
using probetest::GpuTest;

namespace {

// The engine's side: one set layout for both drop-ins (binding 0 a sampled cube, binding 1 a storage
// image), the filter's push constant, a pipeline per drop-in, and one set per dispatch.
struct DropInPipelines {
    VkDevice device;
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pyramid = VK_NULL_HANDLE;
    VkPipeline filter = VK_NULL_HANDLE;
    VkDescriptorPool pool = VK_NULL_HANDLE;

    DropInPipelines(VkDevice d, std::span<const uint32_t> pyramidSpirv, std::span<const uint32_t> filterSpirv, uint32_t maxSets)
        : device(d) {
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
        pyramid = makePipeline(pyramidSpirv);
        filter = makePipeline(filterSpirv);
        const std::array<VkDescriptorPoolSize, 2> sizes{
            {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, maxSets}, {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, maxSets}}};
        VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        poolInfo.maxSets = maxSets;
        poolInfo.poolSizeCount = uint32_t(sizes.size());
        poolInfo.pPoolSizes = sizes.data();
        gpu::vkCheck(vkCreateDescriptorPool(device, &poolInfo, nullptr, &pool), "vkCreateDescriptorPool");
    }
    ~DropInPipelines() {
        vkDestroyDescriptorPool(device, pool, nullptr);
        vkDestroyPipeline(device, filter, nullptr);
        vkDestroyPipeline(device, pyramid, nullptr);
        vkDestroyPipelineLayout(device, layout, nullptr);
        vkDestroyDescriptorSetLayout(device, setLayout, nullptr);
    }
    DropInPipelines(const DropInPipelines&) = delete;
    DropInPipelines& operator=(const DropInPipelines&) = delete;

    VkPipeline makePipeline(std::span<const uint32_t> spirv) const {
        VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        moduleInfo.codeSize = spirv.size_bytes();
        moduleInfo.pCode = spirv.data();
        VkShaderModule module;
        gpu::vkCheck(vkCreateShaderModule(device, &moduleInfo, nullptr, &module), "vkCreateShaderModule");
        VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        info.stage = {
            VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_COMPUTE_BIT, module, "main", nullptr};
        info.layout = layout;
        VkPipeline pipeline;
        gpu::vkCheck(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline), "vkCreateComputePipelines");
        vkDestroyShaderModule(device, module, nullptr);
        return pipeline;
    }

    // A set of `sampled` (in `sampledLayout`) through `sampler` and `storage` (GENERAL), bound.
    void bind(VkCommandBuffer cmd, VkImageView sampled, VkImageLayout sampledLayout, VkSampler sampler, VkImageView storage) const {
        VkDescriptorSetAllocateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        info.descriptorPool = pool;
        info.descriptorSetCount = 1;
        info.pSetLayouts = &setLayout;
        VkDescriptorSet set;
        gpu::vkCheck(vkAllocateDescriptorSets(device, &info, &set), "vkAllocateDescriptorSets");
        const VkDescriptorImageInfo sampledInfo{sampler, sampled, sampledLayout};
        const VkDescriptorImageInfo storageInfo{VK_NULL_HANDLE, storage, VK_IMAGE_LAYOUT_GENERAL};
        std::array<VkWriteDescriptorSet, 2> writes{};
        for (uint32_t b = 0; b < 2; ++b) {
            writes[b] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            writes[b].dstSet = set;
            writes[b].dstBinding = b;
            writes[b].descriptorCount = 1;
            writes[b].descriptorType = b == 0 ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER : VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
            writes[b].pImageInfo = b == 0 ? &sampledInfo : &storageInfo;
        }
        vkUpdateDescriptorSets(device, uint32_t(writes.size()), writes.data(), 0, nullptr);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set, 0, nullptr);
    }
};

// What the drop-ins wrote: the pyramid (mip 0 the source) and the output levels (level 0 left empty:
// an engine copies it).
struct DropInResult {
    CubeLevels pyramid;
    CubeLevels levels;
};

// Unpacks `regions` of `buffer` (`format` texels) into cube images, from region `first` on.
CubeLevels unpackLevels(const gpu::Buffer& buffer, const std::vector<VkBufferImageCopy>& regions, VkFormat format, int first) {
    CubeLevels result;
    const auto* data = static_cast<const std::byte*>(buffer.mapped());
    for (int m = 0; m < int(regions.size()); ++m) {
        CubeImage level(int(regions[m].imageExtent.width));
        level.rgb.clear();
        if (m >= first) gpu::unpackTexels(data + regions[m].bufferOffset, texelCount(level.size), format, level.rgb);
        result.push_back(std::move(level));
    }
    return result;
}

DropInResult runDropIns(const TapTable& table, std::span<const uint32_t> pyramidSpirv, std::span<const uint32_t> filterSpirv,
                        const CubeImage& source, VkFormat format) {
    const gpu::Device& device = probetest::testDevice();
    const VkDevice vk = device.device();
    const int size = table.faceSize, levels = table.levelCount, mips = int(std::log2(size)) + 1;
    const gpu::CubeImageResource pyramidImage(device, size, mips, format,
                                              VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                                                  VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    const gpu::CubeImageResource outputImage(device, size, levels, format, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    const std::vector<VkBufferImageCopy> pyramidRegions = probetest::levelRegions(size, mips, gpu::texelBytes(format)),
                                         outputRegions = probetest::levelRegions(size, levels, gpu::texelBytes(format));
    const auto bytes = [&](const std::vector<VkBufferImageCopy>& regions) {
        const VkBufferImageCopy& last = regions.back();
        return last.bufferOffset + texelCount(int(last.imageExtent.width)) * gpu::texelBytes(format);
    };
    gpu::Buffer staging(device, texelCount(size) * gpu::texelBytes(format), gpu::Buffer::Kind::staging);
    auto* texels = static_cast<std::byte*>(staging.mapped());
    for (std::size_t t = 0; t < texelCount(size); ++t) {
        const float rgba[4] = {source.rgb[3 * t], source.rgb[3 * t + 1], source.rgb[3 * t + 2], 1.0f};
        if (format == VK_FORMAT_R16G16B16A16_SFLOAT) {
            const uint16_t half[4] = {glm::packHalf1x16(rgba[0]), glm::packHalf1x16(rgba[1]), glm::packHalf1x16(rgba[2]),
                                      glm::packHalf1x16(rgba[3])};
            std::memcpy(texels + t * sizeof(half), half, sizeof(half));
        } else {
            std::memcpy(texels + t * sizeof(rgba), rgba, sizeof(rgba));
        }
    }
    gpu::Buffer pyramidBack(device, bytes(pyramidRegions), gpu::Buffer::Kind::staging);
    gpu::Buffer outputBack(device, bytes(outputRegions), gpu::Buffer::Kind::staging);

    const gpu::ImageView pyramidView(vk, pyramidImage.handle(), format, VK_IMAGE_VIEW_TYPE_CUBE, 0, uint32_t(mips));
    std::vector<gpu::ImageView> mipCubes, mipArrays, outputViews;
    for (int k = 0; k < mips; ++k) {
        mipCubes.emplace_back(vk, pyramidImage.handle(), format, VK_IMAGE_VIEW_TYPE_CUBE, uint32_t(k), 1u);
        mipArrays.emplace_back(vk, pyramidImage.handle(), format, VK_IMAGE_VIEW_TYPE_2D_ARRAY, uint32_t(k), 1u);
    }
    for (int m = 0; m < levels; ++m)
        outputViews.emplace_back(vk, outputImage.handle(), format, VK_IMAGE_VIEW_TYPE_2D_ARRAY, uint32_t(m), 1u);
    const gpu::Sampler sampler(vk, true);
    const DropInPipelines dropIn(vk, pyramidSpirv, filterSpirv, uint32_t(mips + levels));
    const auto groups = [](int faceSize) { return uint32_t(faceSize + 7) / 8; };

    gpu::Submission submission(device);
    VkCommandBuffer cmd = submission.begin();
    // The source into mip 0; every mip GENERAL while the pyramid is built.
    gpu::imageBarrier(cmd, pyramidImage.handle(), 0, uint32_t(mips), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    vkCmdCopyBufferToImage(cmd, staging.handle(), pyramidImage.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, pyramidRegions.data());
    gpu::imageBarrier(cmd, pyramidImage.handle(), 0, uint32_t(mips), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, dropIn.pyramid);
    for (int k = 1; k < mips; ++k) { // mip k from mip k - 1
        dropIn.bind(cmd, mipCubes[k - 1].handle(), VK_IMAGE_LAYOUT_GENERAL, sampler.handle(), mipArrays[k].handle());
        vkCmdDispatch(cmd, groups(size >> k), groups(size >> k), 6);
        gpu::imageBarrier(cmd, pyramidImage.handle(), uint32_t(k), 1, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                          VK_ACCESS_SHADER_READ_BIT);
    }
    gpu::imageBarrier(cmd, pyramidImage.handle(), 0, uint32_t(mips), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                      VK_ACCESS_SHADER_READ_BIT);
    gpu::imageBarrier(cmd, outputImage.handle(), 0, uint32_t(levels), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, dropIn.filter);
    for (int m = 1; m < levels; ++m) { // level 0 is a copy of the source, not the shader's
        dropIn.bind(cmd, pyramidView.handle(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, sampler.handle(), outputViews[m].handle());
        const int32_t level = m;
        vkCmdPushConstants(cmd, dropIn.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(level), &level);
        vkCmdDispatch(cmd, groups(size >> m), groups(size >> m), 6);
    }
    gpu::imageBarrier(cmd, outputImage.handle(), 0, uint32_t(levels), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_ACCESS_TRANSFER_READ_BIT);
    gpu::imageBarrier(cmd, pyramidImage.handle(), 0, uint32_t(mips), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    vkCmdCopyImageToBuffer(cmd, outputImage.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, outputBack.handle(), uint32_t(levels - 1),
                           outputRegions.data() + 1);
    vkCmdCopyImageToBuffer(cmd, pyramidImage.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pyramidBack.handle(), uint32_t(mips),
                           pyramidRegions.data());
    gpu::hostReadBarrier(cmd);
    submission.submitAndWait(cmd);
    submission.release(cmd);
    return {unpackLevels(pyramidBack, pyramidRegions, format, 0), unpackLevels(outputBack, outputRegions, format, 1)};
}

std::filesystem::path committedTable(const std::string& name) { return std::filesystem::path(PROBE_TEST_TABLES) / (name + ".json"); }

// The drop-ins with the table of `tableFile` on a random probe against the CPU model of the same table, on the
// probe as the images hold it (rounded to half floats in RGBA16F). Within hardware sampling's
// tolerance; in RGBA16F each stored value may also be off by 2^-10 of itself (Vulkan lets a conversion
// to a 16-bit float take either neighbour; lavapipe's mip 1 is off by that), at most 9 times over (the
// source and eight mips at 128^2, or a level).
void expectDropInsEqualModel(const std::filesystem::path& tableFile, std::span<const uint32_t> pyramidSpirv,
                             std::span<const uint32_t> filterSpirv, VkFormat format) {
    const TapTable table = readTable(tableFile);
    const std::string tableName = tableFile.stem().string();
    CubeImage source = probetest::randomProbe(table.faceSize, 31);
    const bool half = format == VK_FORMAT_R16G16B16A16_SFLOAT;
    if (half)
        for (float& v : source.rgb) v = glm::unpackHalf1x16(glm::packHalf1x16(v));
    const CubeLevels pyramid = buildPyramid(source, table.pyramid);
    const CubeLevels expected = tableFilter(pyramid, table);
    const DropInResult result = runDropIns(table, pyramidSpirv, filterSpirv, source, format);
    const double tolerance = probetest::kSamplingCases[1].tolerance + (half ? 9 * std::ldexp(1.0, -10) : 0.0);
    ASSERT_EQ(result.pyramid.size(), pyramid.size());
    for (std::size_t k = 1; k < pyramid.size(); ++k) {
        const double error = probetest::maxRelativeError(result.pyramid[k], pyramid[k]);
        ::testing::Test::RecordProperty(fmt::format("{} pyramid mip {}", tableName, k), fmt::format("{:.3g}", error));
        EXPECT_LT(error, tolerance) << tableName << ", pyramid mip " << k;
    }
    for (int m = 1; m < table.levelCount; ++m) {
        const double error = probetest::maxRelativeError(result.levels[m], expected[m]);
        ::testing::Test::RecordProperty(fmt::format("{} level {}", tableName, m), fmt::format("{:.3g}", error));
        EXPECT_LT(error, tolerance) << tableName << ", level " << m;
    }
}

TEST_F(GpuTest, EngineDropInShadersWithTheDefaultTableEqualCpuModel) {
    expectDropInsEqualModel(committedTable("gltf128_quad8"), kEnginePyramidGltf128Quad8Spv, kEngineGltf128Quad8Spv,
                            VK_FORMAT_R32G32B32A32_SFLOAT);
}

TEST_F(GpuTest, EngineDropInShadersWithAConstantTableEqualCpuModel) {
    expectDropInsEqualModel(committedTable("gltf128_const8"), kEnginePyramidGltf128Const8Spv, kEngineGltf128Const8Spv,
                            VK_FORMAT_R32G32B32A32_SFLOAT);
}

// Compiled with no defines, as docs/engine.md shows them: RGBA16F images.
TEST_F(GpuTest, EngineDropInShadersWithTheirDefaultFormatEqualCpuModel) {
    expectDropInsEqualModel(committedTable("gltf128_const8"), kEnginePyramidGltf128Const8HalfSpv, kEngineGltf128Const8HalfSpv,
                            VK_FORMAT_R16G16B16A16_SFLOAT);
}

// A table whose levels use one and two groups of four taps in turn (probefit mix of gltf128_const8 and
// gltf128_const4, padded with zero weights): the filter reads each level's count.
TEST_F(GpuTest, EngineDropInShadersWithAMixedTableEqualCpuModel) {
    expectDropInsEqualModel(PROBE_TEST_MIXED_TABLE, kEnginePyramidGltf128ConstMixSpv, kEngineGltf128ConstMixSpv,
                            VK_FORMAT_R32G32B32A32_SFLOAT);
}

// Finite input gives finite output through the drop-ins too: a source at the largest magnitude they
// accept (+-2^64 in RGBA32F, whose mip 0 the engine clamps there; +-65504, the largest half, in
// RGBA16F) with 0 and -0 beside it gives finite pyramid mips and levels no larger in magnitude, and a
// source all at that value gives it back at every mip and level (the weights sum to 1 without
// overflow): to float rounding, or in RGBA16F to 2^-10 per stored value as above.
TEST_F(GpuTest, EngineDropInShadersStayFiniteAtTheLargestValuesTheyAccept) {
    const TapTable table = readTable(committedTable("gltf128_const8"));
    const struct {
        VkFormat format;
        float largest;
        std::span<const uint32_t> pyramid, filter;
    } cases[] = {{VK_FORMAT_R32G32B32A32_SFLOAT, float(PROBE_FILTER_RANGE_LIMIT), kEnginePyramidGltf128Const8Spv, kEngineGltf128Const8Spv},
                 {VK_FORMAT_R16G16B16A16_SFLOAT, 65504.0f, kEnginePyramidGltf128Const8HalfSpv, kEngineGltf128Const8HalfSpv}};
    for (const auto& c : cases) {
        const double tolerance = c.format == VK_FORMAT_R16G16B16A16_SFLOAT ? 9 * std::ldexp(1.0, -10) : 1e-6;
        CubeImage mixed(table.faceSize);
        for (std::size_t t = 0; t < texelCount(mixed.size); ++t) {
            const float values[4] = {c.largest, 0.0f, -c.largest, -0.0f};
            mixed.set(t, {values[t % 4], values[(t + 1) % 4], values[(t + 2) % 4]});
        }
        const DropInResult result = runDropIns(table, c.pyramid, c.filter, mixed, c.format);
        for (const CubeLevels* images : {&result.pyramid, &result.levels})
            for (const CubeImage& image : *images)
                for (float v : image.rgb) ASSERT_TRUE(std::isfinite(v) && std::abs(v) <= c.largest) << v << " at size " << image.size;
        const DropInResult flat = runDropIns(table, c.pyramid, c.filter, CubeImage(table.faceSize, glm::vec3(c.largest)), c.format);
        for (std::size_t k = 1; k < flat.pyramid.size(); ++k)
            EXPECT_LT(probetest::maxRelativeError(flat.pyramid[k], CubeImage(flat.pyramid[k].size, glm::vec3(c.largest))), tolerance)
                << "mip " << k;
        for (int m = 1; m < table.levelCount; ++m)
            EXPECT_LT(probetest::maxRelativeError(flat.levels[m], CubeImage(flat.levels[m].size, glm::vec3(c.largest))), tolerance)
                << "level " << m;
    }
}

} // namespace
