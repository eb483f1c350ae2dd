// SH projection on the GPU (shaders/sh_projection.comp): the source and its geometry in, one
// dispatch that sums the texels into blocks of 1024, then dispatches that sum blocks of 1024
// blocks, until one block (9 RGB coefficients) is left.
#include <cmath>
#include <cstdint>

#include <fmt/format.h>
#include <sh_projection.spv.h>

#include "compute_pipeline.h"
#include "gpu_timer.h"
#include "probe/error.h"
#include "probe/range_scale.h"
#include "submission.h"

namespace probe::gpu {

namespace {

constexpr uint32_t kItemsPerGroup = 1024;   // ITEMS_PER_GROUP of the shader
constexpr uint32_t kBlockTexels = kShCount; // one vec4 per coefficient

struct ShConstants {
    uint32_t count;
    uint32_t inFirst;
    uint32_t outFirst;
    uint32_t fromSource;
};

uint32_t blocksFor(uint32_t items) { return (items + kItemsPerGroup - 1) / kItemsPerGroup; }

} // namespace

struct ShProjector::Impl {
    const Device& device;
    int faceSize;
    Buffer source, blocks, geometry, unused;
    std::unique_ptr<PipelineLayout> layout;
    std::unique_ptr<ComputePipeline> pipeline;
    std::unique_ptr<GpuTimer> timer;
    std::unique_ptr<Submission> submission;
    std::vector<ShConstants> stages; // in dispatch order; the last one leaves one block
    std::vector<Dispatch> dispatches;

    Impl(const Device& d, int size) : device(d), faceSize(size) {
        if (log2Exact(size) < 0) throw ProbeError(fmt::format("SH projection: face size {} is not a power of two", size));
        const auto texels = static_cast<uint32_t>(texelCount(size));
        uint32_t items = texels, inFirst = 0, outFirst = 0;
        for (bool fromSource = true; fromSource || items > 1; fromSource = false) {
            stages.push_back({items, inFirst, outFirst, fromSource ? 1u : 0u});
            inFirst = outFirst;
            items = blocksFor(items);
            outFirst += items * kBlockTexels;
        }
        std::vector<float> geometryData;
        const CubeGeometry g(size);
        for (std::size_t t = 0; t < texels; ++t)
            for (double value : {g.directions[t].x, g.directions[t].y, g.directions[t].z, g.solidAngles[t]})
                geometryData.push_back(static_cast<float>(value));

        constexpr VkDeviceSize texelBytes = 4 * sizeof(float);
        source = Buffer(d, texels * texelBytes, Buffer::Kind::texels);
        blocks = Buffer(d, outFirst * texelBytes, Buffer::Kind::storage);
        geometry = Buffer(d, texels * texelBytes, Buffer::Kind::texels);
        unused = Buffer(d, texelBytes, Buffer::Kind::storage);
        layout = std::make_unique<PipelineLayout>(d, std::array<const Buffer*, kBufferCount>{&source, &blocks, &geometry, &unused});
        pipeline = std::make_unique<ComputePipeline>(d.device(), *layout, kShProjectionSpv);
        timer = std::make_unique<GpuTimer>(d, std::vector<std::string>{"sh"});
        submission = std::make_unique<Submission>(d);
        submission->upload(geometry, geometryData.data(), geometry.bytes());
    }
};

ShProjector::ShProjector(const Device& device, int faceSize) : impl_(std::make_unique<Impl>(device, faceSize)) {}
ShProjector::~ShProjector() = default;

ShCoefficients ShProjector::project(const CubeImage& source) {
    Impl& p = *impl_;
    if (source.size != p.faceSize)
        throw ProbeError(fmt::format("SH projection: the probe has face size {}, the projector was built for {}", source.size, p.faceSize));
    const int shift = rangeShift(source); // probe/range_scale.h: the float sums stay finite
    const std::vector<float> texels = rgbaTexels(shifted(source, -shift));
    p.submission->upload(p.source, texels.data(), p.source.bytes());

    VkCommandBuffer commandBuffer = p.submission->begin();
    p.dispatches.clear();
    p.timer->reset(commandBuffer);
    computeBarrier(commandBuffer);
    p.layout->bind(commandBuffer);
    p.timer->boundary(commandBuffer, 0);
    for (std::size_t k = 0; k < p.stages.size(); ++k) {
        if (k > 0) computeBarrier(commandBuffer);
        const ShConstants& stage = p.stages[k];
        const uint32_t groups = blocksFor(stage.count);
        p.pipeline->dispatch(commandBuffer, std::as_bytes(std::span(&stage, 1)), groups);
        p.dispatches.push_back({"sh", static_cast<int>(k), groups});
    }
    computeBarrier(commandBuffer);
    p.timer->boundary(commandBuffer, 1);
    p.timer->clear();
    p.submission->submitAndWait(commandBuffer);
    p.submission->release(commandBuffer);
    p.timer->collect();

    std::vector<float> all(p.blocks.bytes() / sizeof(float));
    p.submission->download(p.blocks, all.data(), p.blocks.bytes());
    ShCoefficients coefficients{};
    const float* block = all.data() + 4 * std::size_t(p.stages.back().outFirst);
    for (int c = 0; c < kShCount; ++c)
        coefficients[c] = std::ldexp(1.0, shift) * glm::dvec3(block[4 * c], block[4 * c + 1], block[4 * c + 2]);
    return coefficients;
}

std::vector<PassTime> ShProjector::timings() const { return impl_->timer->timings(); }

const std::vector<Dispatch>& ShProjector::dispatches() const { return impl_->dispatches; }

} // namespace probe::gpu
