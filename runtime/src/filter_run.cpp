// Filter's tools' path: the probes uploaded into a set's own source cubes, the passes run and timed,
// the levels read back; one probe or a batch, or one probe in slices; and the pyramid read back.
#include <algorithm>

#include <fmt/format.h>

#include "filter_impl.h"
#include "probe/error.h"
#include "probe/limits.h"
#include "probe/range_scale.h"
#include "vulkan_check.h"

namespace probe::gpu {

namespace {

// The levels 0..depth of the pyramid buffer's first cube (of a batch of `cubes`), inside the faces.
CubeLevels unpackPyramid(const float* texels, const std::vector<uint32_t>& offsets, int cubes, int faceSize, int depth) {
    CubeLevels result;
    for (int m = 0; m <= depth; ++m) {
        CubeImage level(faceSize >> m);
        const float* first = texels + 4 * std::size_t(cubes) * offsets[m];
        for (int f = 0; f < kFaceCount; ++f)
            for (int j = 0; j < level.size; ++j)
                for (int i = 0; i < level.size; ++i) {
                    const float* c = first + 4 * pyramidTexelIndex(f, i, j, level.size);
                    level.set(texelIndex({f, i, j}, level.size), {c[0], c[1], c[2]});
                }
        result.push_back(std::move(level));
    }
    return result;
}

// A set's own source and output cubes (cube-map arrays for a batch), made at its first run.
void makeRunImages(const Filter::Impl& f, Recording& r) {
    if (r.runSource.handle()) return;
    const FilterSettings& s = f.settings;
    const Device& d = f.device;
    r.runSource = CubeImageResource(d, s.faceSize, 1, VK_FORMAT_R32G32B32A32_SFLOAT,
                                    VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, s.batchSize);
    r.runSourceView =
        ImageView(d.device(), r.runSource.handle(), VK_FORMAT_R32G32B32A32_SFLOAT, f.cubeViewType(), 0, 1, r.runSource.layers());
    f.makeOwnOutput(r);
}

// The probes of a run, uploaded into the set's source cubes, each beyond the range the filter keeps
// scaled down by a power of two; returns each one's power, by which its output is scaled back up once
// read (probe/range_scale.h). The range is an RGBA16F pyramid's 65504 (E5B9G9R9's 65408), else 2^64 for a float32 output;
// a 16-bit output saturates at 65504 anyway, so with a float32 pyramid its source goes as it is (the
// shaders clamp what they read of it to 2^64).
std::vector<int> uploadRunSources(Filter::Impl& f, const Recording& r, std::span<const CubeImage> sources) {
    const FilterSettings& s = f.settings;
    const bool imagePyramid = f.plan.buildsPyramid && f.plan.sampling == Sampling::hardware;
    const double pyramidMax = !imagePyramid                                              ? 0.0
                              : f.plan.pyramidFormat == VK_FORMAT_R16G16B16A16_SFLOAT    ? PROBE_HALF_MAX
                              : f.plan.pyramidFormat == VK_FORMAT_E5B9G9R9_UFLOAT_PACK32 ? PROBE_RGB9E5_MAX
                                                                                         : 0.0;
    const bool float32 = s.outputFormat == VK_FORMAT_R32G32B32A32_SFLOAT;
    std::vector<int> shifts;
    std::vector<float> texels;
    for (const CubeImage& source : sources) {
        const int shift = pyramidMax > 0.0 ? rangeShift(largestMagnitude(source), pyramidMax) : float32 ? rangeShift(source) : 0;
        const std::vector<float> cube = rgbaTexels(shifted(source, -shift));
        texels.insert(texels.end(), cube.begin(), cube.end());
        shifts.push_back(shift);
    }
    Buffer staging(f.device, texels.size() * sizeof(float), Buffer::Kind::staging);
    std::copy(texels.begin(), texels.end(), static_cast<float*>(staging.mapped()));
    VkCommandBuffer upload = f.submission->begin();
    imageBarrier(upload, r.runSource.handle(), 0, 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                 VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    VkBufferImageCopy whole{};
    whole.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, r.runSource.layers()};
    whole.imageExtent = {uint32_t(s.faceSize), uint32_t(s.faceSize), 1};
    vkCmdCopyBufferToImage(upload, staging.handle(), r.runSource.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &whole);
    imageBarrier(upload, r.runSource.handle(), 0, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                 VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                 VK_ACCESS_SHADER_READ_BIT);
    f.submission->submitAndWait(upload);
    f.submission->release(upload);
    return shifts;
}

// The computed levels of each probe in the set's output cubes, read back in the output format (the
// others empty).
std::vector<CubeLevels> readBackRunOutput(Filter::Impl& f, const Recording& r) {
    const FilterSettings& s = f.settings;
    const uint32_t bytesPerTexel = texelBytes(s.outputFormat);
    std::vector<VkBufferImageCopy> regions;
    VkDeviceSize offset = 0;
    for (int m : f.plan.computedLevels) {
        VkBufferImageCopy region{};
        region.bufferOffset = offset;
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), 0, r.runOutput.layers()};
        region.imageExtent = {uint32_t(s.faceSize >> m), uint32_t(s.faceSize >> m), 1};
        regions.push_back(region);
        offset += texelCount(s.faceSize >> m) * s.batchSize * bytesPerTexel;
    }
    Buffer readBack(f.device, offset, Buffer::Kind::staging);
    VkCommandBuffer download = f.submission->begin();
    vkCmdCopyImageToBuffer(download, r.runOutput.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readBack.handle(),
                           uint32_t(regions.size()), regions.data());
    hostReadBarrier(download);
    f.submission->submitAndWait(download);
    f.submission->release(download);
    std::vector<CubeLevels> result(std::size_t(s.batchSize), CubeLevels(s.levelCount));
    for (std::size_t k = 0; k < f.plan.computedLevels.size(); ++k) {
        const int size = s.faceSize >> f.plan.computedLevels[k];
        // The layers of a level follow one another: probe p's six faces after those of p - 1.
        for (std::size_t p = 0; p < result.size(); ++p) {
            CubeImage& level = result[p][f.plan.computedLevels[k]];
            level.size = size;
            level.rgb.clear();
            unpackTexels(static_cast<const unsigned char*>(readBack.mapped()) + regions[k].bufferOffset +
                             p * texelCount(size) * bytesPerTexel,
                         texelCount(size), s.outputFormat, level.rgb);
        }
    }
    return result;
}

// A set for a run, the least recently used of those not in flight (the tools' runs complete before
// they return), made current: checks the probes, makes the set's run images, uploads the probes and
// binds the images to the set; returns the shifts uploadRunSources applied.
std::vector<int> startRun(Filter::Impl& f, std::span<const CubeImage> sources) {
    if (sources.size() != std::size_t(f.settings.batchSize))
        throw ParameterError("batchSize", fmt::format("a run of {} probes, but the filter was built for batches of {}", sources.size(),
                                                      f.settings.batchSize));
    for (const CubeImage& source : sources)
        if (source.size != f.settings.faceSize)
            throw ProbeError(
                fmt::format("filter: the probe has face size {}, the filter was built for {}", source.size, f.settings.faceSize));
    f.acquire();
    Recording& r = *f.current;
    makeRunImages(f, r);
    const std::vector<int> shifts = uploadRunSources(f, r, sources);
    f.bindImages(r.runSourceView.handle(), r.runOutput.handle());
    return shifts;
}

// The run's output cube as an engine's would be laid out: made writable by the passes before them,
// and readable by the read-back after them.
void runOutputBeforePasses(const Filter::Impl& f, const Recording& r, VkCommandBuffer commandBuffer) {
    imageBarrier(commandBuffer, r.runOutput.handle(), 0, uint32_t(f.settings.levelCount), VK_IMAGE_LAYOUT_UNDEFINED, f.ownOutputLayout(),
                 VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
}
void runOutputAfterPasses(const Filter::Impl& f, const Recording& r, VkCommandBuffer commandBuffer) {
    imageBarrier(commandBuffer, r.runOutput.handle(), 0, uint32_t(f.settings.levelCount), f.ownOutputLayout(),
                 VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
}

// Each probe's levels read back and scaled back up by its shift.
std::vector<CubeLevels> finishRun(Filter::Impl& f, const Recording& r, const std::vector<int>& shifts) {
    std::vector<CubeLevels> result = readBackRunOutput(f, r);
    for (std::size_t p = 0; p < result.size(); ++p) {
        shiftLevels(result[p], shifts[p]);
        if (shifts[p] != 0 && f.settings.outputFormat != VK_FORMAT_R32G32B32A32_SFLOAT) saturateTexels(result[p], f.settings.outputFormat);
    }
    return result;
}

} // namespace

void Filter::Impl::makeOwnOutput(Recording& r) const {
    if (r.runOutput.handle()) return;
    const VkImageUsageFlags written = plan.convertOutput ? VK_IMAGE_USAGE_TRANSFER_DST_BIT : VK_IMAGE_USAGE_STORAGE_BIT;
    r.runOutput = CubeImageResource(device, settings.faceSize, settings.levelCount, settings.outputFormat,
                                    written | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, settings.batchSize);
}

VkImageLayout Filter::Impl::ownOutputLayout() const {
    return plan.convertOutput ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_GENERAL;
}

CubeLevels Filter::run(const CubeImage& source, int repeat, Timestamps timestamps) {
    std::vector<CubeLevels> levels = impl_->runBatch(std::span(&source, 1), repeat, timestamps);
    return std::move(levels.front());
}

std::vector<CubeLevels> Filter::run(const std::vector<CubeImage>& sources, int repeat) {
    return impl_->runBatch(sources, repeat, Timestamps::passes);
}

std::vector<CubeLevels> Filter::Impl::runBatch(std::span<const CubeImage> sources, int repeat, Timestamps timestamps) {
    checkRepeat(repeat);
    const std::vector<int> shifts = startRun(*this, sources);
    Recording& r = *current;
    // The passes, recorded once and submitted `repeat` times.
    VkCommandBuffer passes = submission->begin();
    runOutputBeforePasses(*this, r, passes);
    recordPasses(passes, timestamps);
    runOutputAfterPasses(*this, r, passes);
    vkCheck(vkEndCommandBuffer(passes), "vkEndCommandBuffer");
    r.timer->clear();
    for (int k = 0; k < repeat; ++k) {
        submission->submitAndWait(passes, false);
        if (r.timed) r.timer->collect();
    }
    submission->release(passes);
    return finishRun(*this, r, shifts);
}

CubeLevels Filter::run(const CubeImage& source, const std::vector<Slice>& slices, std::vector<double>& sliceMs) {
    Impl& f = *impl_;
    if (slices.empty()) throw ProbeError("filter: no slices to run");
    const std::vector<int> shifts = startRun(f, std::span(&source, 1));
    Recording& r = *f.current;
    sliceMs.clear();
    // One submission a slice, as frames would run them.
    for (std::size_t k = 0; k < slices.size(); ++k) {
        VkCommandBuffer commandBuffer = f.submission->begin();
        if (k == 0) runOutputBeforePasses(f, r, commandBuffer);
        f.recordSlice(commandBuffer, slices[k].pyramid, slices[k].levels, true);
        if (k + 1 == slices.size()) runOutputAfterPasses(f, r, commandBuffer);
        vkCheck(vkEndCommandBuffer(commandBuffer), "vkEndCommandBuffer");
        r.timer->clear();
        f.submission->submitAndWait(commandBuffer, false);
        f.submission->release(commandBuffer);
        if (!r.timed) continue;
        r.timer->collect();
        for (const PassTime& t : r.timer->timings())
            if (t.name == "slice") sliceMs.push_back(t.medianMs);
    }
    return std::move(finishRun(f, r, shifts).front());
}

CubeLevels Filter::downloadPyramid() const {
    Impl& f = *impl_;
    if (!f.plan.buildsPyramid) return {};
    const Recording& r = *f.current;
    if (f.plan.sampling == Sampling::exact) {
        std::vector<float> texels(r.pyramidBuffer.bytes() / sizeof(float));
        f.submission->download(r.pyramidBuffer, texels.data(), r.pyramidBuffer.bytes());
        return unpackPyramid(texels.data(), f.plan.pyramidOffsets, f.settings.batchSize, f.settings.faceSize, f.plan.pyramidDepth);
    }
    const uint32_t bytesPerTexel = texelBytes(f.plan.pyramidFormat);
    std::vector<VkBufferImageCopy> regions;
    VkDeviceSize offset = 0;
    for (int k = 0; k <= f.plan.pyramidDepth; ++k) {
        VkBufferImageCopy region{};
        region.bufferOffset = offset;
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(k), 0, kFaceCount};
        region.imageExtent = {uint32_t(f.settings.faceSize >> k), uint32_t(f.settings.faceSize >> k), 1};
        regions.push_back(region);
        offset += texelCount(f.settings.faceSize >> k) * bytesPerTexel;
    }
    Buffer readBack(f.device, offset, Buffer::Kind::staging);
    VkCommandBuffer download = f.submission->begin();
    const auto mips = uint32_t(r.pyramidImage.mips());
    imageBarrier(download, r.pyramidImage.handle(), 0, mips, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_TRANSFER_READ_BIT);
    vkCmdCopyImageToBuffer(download, r.pyramidImage.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readBack.handle(),
                           uint32_t(regions.size()), regions.data());
    imageBarrier(download, r.pyramidImage.handle(), 0, mips, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                 VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                 VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    hostReadBarrier(download);
    f.submission->submitAndWait(download);
    f.submission->release(download);
    CubeLevels result(f.plan.pyramidDepth + 1);
    for (int k = 0; k <= f.plan.pyramidDepth; ++k) {
        result[k].size = f.settings.faceSize >> k;
        unpackTexels(static_cast<const unsigned char*>(readBack.mapped()) + regions[k].bufferOffset, texelCount(result[k].size),
                     f.plan.pyramidFormat, result[k].rgb);
    }
    return result;
}

} // namespace probe::gpu
