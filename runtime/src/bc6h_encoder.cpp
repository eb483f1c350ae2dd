// BC6H encoding on the GPU (shaders/bc6h_encode.comp): the levels packed in a buffer (uploaded by the
// tools, copied from an engine's output cube by record()), one dispatch over every block of every
// level, the blocks read back level by level or copied into the engine's BC6H cube.
#include <algorithm>
#include <array>
#include <cstdint>

#include <bc6h_encode.spv.h>
#include <fmt/format.h>

#include "compute_pipeline.h"
#include "device.h"
#include "gpu_timer.h"
#include "image.h"
#include "probe/bc6h.h"
#include "probe/error.h"
#include "submission.h"

namespace probe::gpu {

namespace {

constexpr uint32_t kBlocksPerGroup = 64; // the shader's local_size_x
constexpr VkDeviceSize kBlockBytes = 16;

struct Bc6hConstants {
    int32_t faceSize;
    int32_t levelCount;
    uint32_t firstBlock;
    uint32_t blockCount;
    uint32_t texelBase;
};

// The blocks one dispatch encodes: a run of whole faces whose texels the binding holds, through a
// window of the texel buffer where the levels exceed the device's storage-buffer range (RGBA32F
// levels of 2048^2 take 512 MiB, and every device guarantees 128 MiB).
struct Chunk {
    uint32_t firstBlock = 0, blockCount = 0;
    uint32_t texelBase = 0; // the window's first texel
    std::unique_ptr<PipelineLayout> layout;
};

} // namespace

struct Bc6hEncoder::Impl {
    const Device& device;
    int faceSize, levelCount;
    std::vector<std::size_t> levelBytes;
    std::vector<std::size_t> levelTexels; // first texel of each level in `texels`
    Buffer texels, blocks, unused;
    std::unique_ptr<PipelineLayout> layout;
    std::unique_ptr<ComputePipeline> pipeline;     // RGBA32F texels
    std::unique_ptr<ComputePipeline> halfPipeline; // RGBA16F texels: made at the first record() of such a cube
    std::unique_ptr<GpuTimer> timer;
    std::unique_ptr<Submission> submission;
    std::array<std::vector<Chunk>, 2> chunks; // for RGBA32F and RGBA16F texels: made at first use

    Impl(const Device& d, int size, int levels) : device(d), faceSize(size), levelCount(levels) {
        validateSizeAndLevels(size, levels);
        std::size_t texelTotal = 0, blockBytes = 0;
        for (int m = 0; m < levels; ++m) {
            levelTexels.push_back(texelTotal);
            texelTotal += texelCount(std::max(size >> m, 1));
            levelBytes.push_back(bc6hLevelBytes(std::max(size >> m, 1)));
            blockBytes += levelBytes.back();
        }
        texels = Buffer(d, texelTotal * 4 * sizeof(float), Buffer::Kind::texels);
        blocks = Buffer(d, blockBytes, Buffer::Kind::storage);
        unused = Buffer(d, kBlockBytes, Buffer::Kind::storage);
        layout = std::make_unique<PipelineLayout>(d, std::array<const Buffer*, kBufferCount>{&blocks, &texels, &unused, &unused});
        pipeline = std::make_unique<ComputePipeline>(d.device(), *layout, kBc6hEncodeSpv);
        timer = std::make_unique<GpuTimer>(d, std::vector<std::string>{"bc6h"});
        submission = std::make_unique<Submission>(d);
    }

    // The dispatches over every block of texels of `texelBytes`, each face's texels within one window.
    const std::vector<Chunk>& chunksFor(VkDeviceSize texelBytes) {
        std::vector<Chunk>& list = chunks[texelBytes == 8 ? 1 : 0];
        if (!list.empty()) return list;
        const VkPhysicalDeviceLimits& limits = device.impl().limits;
        const VkDeviceSize alignment = std::max<VkDeviceSize>(limits.minStorageBufferOffsetAlignment, texelBytes);
        std::vector<VkDeviceSize> ends; // each chunk's end in bytes
        uint32_t block = 0;
        VkDeviceSize texel = 0;
        for (int m = 0; m < levelCount; ++m) {
            const int size = std::max(faceSize >> m, 1);
            const auto faceBlocks = uint32_t(bc6hLevelBytes(size) / kBlockBytes / 6);
            const VkDeviceSize faceTexels = VkDeviceSize(size) * VkDeviceSize(size);
            for (int face = 0; face < 6; ++face, block += faceBlocks, texel += faceTexels) {
                const VkDeviceSize end = (texel + faceTexels) * texelBytes;
                if (!list.empty() && end - list.back().texelBase * texelBytes <= limits.maxStorageBufferRange) {
                    list.back().blockCount += faceBlocks;
                    ends.back() = end;
                    continue;
                }
                list.push_back({block, faceBlocks, uint32_t(texel * texelBytes / alignment * alignment / texelBytes), nullptr});
                ends.push_back(end);
            }
        }
        for (std::size_t c = 0; c < list.size(); ++c) {
            const VkDeviceSize offset = list[c].texelBase * texelBytes;
            list[c].layout =
                std::make_unique<PipelineLayout>(device, std::array<const Buffer*, kBufferCount>{&blocks, &texels, &unused, &unused},
                                                 BufferWindow{1, offset, ends[c] - offset});
        }
        return list;
    }

    // Every chunk's dispatch of `pipeline`.
    void dispatch(VkCommandBuffer commandBuffer, const ComputePipeline& encode, VkDeviceSize texelBytes) {
        for (const Chunk& c : chunksFor(texelBytes)) {
            c.layout->bind(commandBuffer);
            const Bc6hConstants constants{faceSize, levelCount, c.firstBlock, c.blockCount, c.texelBase};
            encode.dispatch(commandBuffer, std::as_bytes(std::span(&constants, 1)), (c.blockCount + kBlocksPerGroup - 1) / kBlocksPerGroup);
        }
    }
};

Bc6hEncoder::Bc6hEncoder(const Device& device, int faceSize, int levelCount)
    : impl_(std::make_unique<Impl>(device, faceSize, levelCount)) {}
Bc6hEncoder::~Bc6hEncoder() = default;

std::vector<std::vector<uint8_t>> Bc6hEncoder::encode(const CubeLevels& levels) {
    Impl& e = *impl_;
    if (int(levels.size()) != e.levelCount)
        throw ProbeError(fmt::format("BC6H: {} levels, the encoder was built for {}", levels.size(), e.levelCount));
    std::vector<float> packed;
    packed.reserve(e.texels.bytes() / sizeof(float));
    for (int m = 0; m < e.levelCount; ++m) {
        const int size = std::max(e.faceSize >> m, 1);
        // A level not computed (empty) encodes as black.
        if (levels[m].size != 0 && levels[m].size != size)
            throw ProbeError(fmt::format("BC6H: level {} has face size {}, not {}", m, levels[m].size, size));
        for (std::size_t t = 0; t < texelCount(size); ++t) {
            const glm::vec3 c = levels[m].size ? levels[m].texel(t) : glm::vec3(0.0f);
            packed.insert(packed.end(), {c.r, c.g, c.b, 1.0f});
        }
    }
    e.submission->upload(e.texels, packed.data(), e.texels.bytes());

    VkCommandBuffer commandBuffer = e.submission->begin();
    e.timer->reset(commandBuffer);
    computeBarrier(commandBuffer);
    e.timer->boundary(commandBuffer, 0);
    e.dispatch(commandBuffer, *e.pipeline, 16);
    computeBarrier(commandBuffer);
    e.timer->boundary(commandBuffer, 1);
    e.timer->clear();
    e.submission->submitAndWait(commandBuffer);
    e.submission->release(commandBuffer);
    e.timer->collect();

    std::vector<uint8_t> all(e.blocks.bytes());
    e.submission->download(e.blocks, all.data(), e.blocks.bytes());
    std::vector<std::vector<uint8_t>> result;
    std::size_t offset = 0;
    for (std::size_t bytes : e.levelBytes) {
        result.emplace_back(all.begin() + std::ptrdiff_t(offset), all.begin() + std::ptrdiff_t(offset + bytes));
        offset += bytes;
    }
    return result;
}

void Bc6hEncoder::record(VkCommandBuffer commandBuffer, const OutputCube& source, VkImage target) {
    Impl& e = *impl_;
    const auto refuse = [](const std::string& field, const std::string& problem) {
        return ProbeError(fmt::format("Bc6hEncoder::record: {} {}", field, problem));
    };
    if (source.image == VK_NULL_HANDLE) throw refuse("source.image", "is VK_NULL_HANDLE");
    if (source.format != VK_FORMAT_R32G32B32A32_SFLOAT && source.format != VK_FORMAT_R16G16B16A16_SFLOAT)
        throw refuse("source.format", fmt::format("is {}: the encoder reads RGBA32F or RGBA16F cubes", int(source.format)));
    if (source.faceSize != uint32_t(e.faceSize))
        throw refuse("source.faceSize", fmt::format("is {}, but the encoder was built for {}", source.faceSize, e.faceSize));
    if (source.mipLevels < uint32_t(e.levelCount))
        throw refuse("source.mipLevels", fmt::format("is {}, but the encoder reads {} levels", source.mipLevels, e.levelCount));
    if (source.arrayLayers != 6) throw refuse("source.arrayLayers", fmt::format("is {}, not the 6 faces of a cube", source.arrayLayers));
    if (!(source.usage & VK_IMAGE_USAGE_TRANSFER_SRC_BIT))
        throw refuse("source.usage", "lacks TRANSFER_SRC, which the encoder copies it by");
    if (target == VK_NULL_HANDLE) throw refuse("target", "is VK_NULL_HANDLE");

    // The source's writes (a filter's compute writes, or its conversion's copy) and this encoder's
    // earlier use of its buffers, before the copies; the source in TRANSFER_SRC_OPTIMAL for its copy.
    const VkPipelineStageFlags computeAndTransfer = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    const VkAccessFlags written = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    const auto barrier = [&](VkPipelineStageFlags from, VkAccessFlags made, VkPipelineStageFlags to, VkAccessFlags accessed) {
        VkMemoryBarrier memory{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, made, accessed};
        vkCmdPipelineBarrier(commandBuffer, from, to, 0, 1, &memory, 0, nullptr, 0, nullptr);
    };
    barrier(computeAndTransfer, written, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    imageBarrier(commandBuffer, source.image, 0, uint32_t(e.levelCount), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 computeAndTransfer, written, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    const VkDeviceSize texelBytes = source.format == VK_FORMAT_R16G16B16A16_SFLOAT ? 8 : 16;
    std::vector<VkBufferImageCopy> reads, writes;
    VkDeviceSize blockOffset = 0;
    for (int m = 0; m < e.levelCount; ++m) {
        const uint32_t size = uint32_t(std::max(e.faceSize >> m, 1));
        const VkImageSubresourceLayers faces{VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), 0, 6};
        reads.push_back({e.levelTexels[m] * texelBytes, 0, 0, faces, {0, 0, 0}, {size, size, 1}});
        writes.push_back({blockOffset, 0, 0, faces, {0, 0, 0}, {size, size, 1}});
        blockOffset += e.levelBytes[m];
    }
    vkCmdCopyImageToBuffer(commandBuffer, source.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, e.texels.handle(), uint32_t(reads.size()),
                           reads.data());
    imageBarrier(commandBuffer, source.image, 0, uint32_t(e.levelCount), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                 VK_PIPELINE_STAGE_TRANSFER_BIT, 0, computeAndTransfer,
                 VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
    barrier(VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    if (texelBytes == 8 && !e.halfPipeline) {
        const std::array<int32_t, 1> half{1}; // the shader's kHalfTexels
        e.halfPipeline = std::make_unique<ComputePipeline>(e.device.device(), *e.layout, kBc6hEncodeSpv, half);
    }
    e.dispatch(commandBuffer, texelBytes == 8 ? *e.halfPipeline : *e.pipeline, texelBytes);
    barrier(VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    vkCmdCopyBufferToImage(commandBuffer, e.blocks.handle(), target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, uint32_t(writes.size()),
                           writes.data());
}

std::vector<PassTime> Bc6hEncoder::timings() const { return impl_->timer->timings(); }

} // namespace probe::gpu
