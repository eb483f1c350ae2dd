// BC6H encoding on the GPU (shaders/bc6h_encode.comp): the levels uploaded packed, one dispatch over
// every block of every level, the blocks read back level by level.
#include <algorithm>
#include <cstdint>

#include <bc6h_encode.spv.h>
#include <fmt/format.h>

#include "compute_pipeline.h"
#include "gpu_timer.h"
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
    uint32_t blockCount;
};

} // namespace

struct Bc6hEncoder::Impl {
    const Device& device;
    int faceSize, levelCount;
    std::vector<std::size_t> levelBytes;
    Buffer texels, blocks, unused;
    std::unique_ptr<PipelineLayout> layout;
    std::unique_ptr<ComputePipeline> pipeline;
    std::unique_ptr<GpuTimer> timer;
    std::unique_ptr<Submission> submission;

    Impl(const Device& d, int size, int levels) : device(d), faceSize(size), levelCount(levels) {
        validateSizeAndLevels(size, levels);
        std::size_t texelTotal = 0, blockBytes = 0;
        for (int m = 0; m < levels; ++m) {
            texelTotal += texelCount(std::max(size >> m, 1));
            levelBytes.push_back(bc6hLevelBytes(std::max(size >> m, 1)));
            blockBytes += levelBytes.back();
        }
        texels = Buffer(d, texelTotal * 4 * sizeof(float), Buffer::Kind::storage);
        blocks = Buffer(d, blockBytes, Buffer::Kind::storage);
        unused = Buffer(d, kBlockBytes, Buffer::Kind::storage);
        layout = std::make_unique<PipelineLayout>(d, std::array<const Buffer*, kBufferCount>{&blocks, &texels, &unused, &unused});
        pipeline = std::make_unique<ComputePipeline>(d.device(), *layout, kBc6hEncodeSpv);
        timer = std::make_unique<GpuTimer>(d, std::vector<std::string>{"bc6h"});
        submission = std::make_unique<Submission>(d);
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

    const auto blockCount = static_cast<uint32_t>(e.blocks.bytes() / kBlockBytes);
    VkCommandBuffer commandBuffer = e.submission->begin();
    e.timer->reset(commandBuffer);
    computeBarrier(commandBuffer);
    e.layout->bind(commandBuffer);
    e.timer->boundary(commandBuffer, 0);
    const Bc6hConstants constants{e.faceSize, e.levelCount, blockCount};
    e.pipeline->dispatch(commandBuffer, std::as_bytes(std::span(&constants, 1)), (blockCount + kBlocksPerGroup - 1) / kBlocksPerGroup);
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

std::vector<PassTime> Bc6hEncoder::timings() const { return impl_->timer->timings(); }

} // namespace probe::gpu
