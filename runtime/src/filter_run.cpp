// Filter's tools' path: the probe uploaded into a set's own source cube, the passes run and timed,
// the levels read back; one probe, one probe in slices, or a batch of probes in one submission; and
// the pyramid read back.
#include <algorithm>

#include <fmt/format.h>

#include "filter_impl.h"
#include "probe/error.h"
#include "probe/limits.h"
#include "probe/range_scale.h"
#include "vulkan_check.h"

namespace probe::gpu {

namespace {

// The levels 0..depth of the pyramid buffer, inside the faces.
CubeLevels unpackPyramid(const float* texels, const std::vector<uint32_t>& offsets, int faceSize, int depth) {
    CubeLevels result;
    for (int m = 0; m <= depth; ++m) {
        CubeImage level(faceSize >> m);
        const float* first = texels + 4 * std::size_t(offsets[m]);
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

// A set's own source and output cubes, made at its first run.
void makeRunImages(const Filter::Impl& f, Recording& r) {
    if (r.runSource.handle()) return;
    const FilterSettings& s = f.settings;
    const Device& d = f.device;
    r.runSource =
        CubeImageResource(d, s.faceSize, 1, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
    r.runSourceView = ImageView(d.device(), r.runSource.handle(), VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_VIEW_TYPE_CUBE, 0, 1);
    const VkImageUsageFlags written = f.plan.convertOutput ? VK_IMAGE_USAGE_TRANSFER_DST_BIT : VK_IMAGE_USAGE_STORAGE_BIT;
    r.runOutput = CubeImageResource(d, s.faceSize, s.levelCount, s.outputFormat, written | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
}

// The source of a run, uploaded into the set's source cube, beyond the range the filter keeps scaled
// down by a power of two; returns that power, by which the output is scaled back up once read
// (probe/range_scale.h). The range is an RGBA16F pyramid's 65504, else 2^64 for a float32 output; a
// 16-bit output saturates at 65504 anyway, so with a float32 pyramid its source goes as it is (the
// shaders clamp what they read of it to 2^64).
int uploadRunSource(Filter::Impl& f, const Recording& r, const CubeImage& source) {
    const FilterSettings& s = f.settings;
    const bool halfPyramid =
        f.plan.buildsPyramid && f.plan.sampling == Sampling::hardware && f.plan.pyramidFormat == VK_FORMAT_R16G16B16A16_SFLOAT;
    const bool float32 = s.outputFormat == VK_FORMAT_R32G32B32A32_SFLOAT;
    const int shift = halfPyramid ? rangeShift(largestMagnitude(source), PROBE_HALF_MAX) : float32 ? rangeShift(source) : 0;
    const std::vector<float> texels = rgbaTexels(shifted(source, -shift));
    Buffer staging(f.device, texels.size() * sizeof(float), Buffer::Kind::staging);
    std::copy(texels.begin(), texels.end(), static_cast<float*>(staging.mapped()));
    VkCommandBuffer upload = f.submission->begin();
    imageBarrier(upload, r.runSource.handle(), 0, 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                 VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    VkBufferImageCopy whole{};
    whole.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, kFaceCount};
    whole.imageExtent = {uint32_t(s.faceSize), uint32_t(s.faceSize), 1};
    vkCmdCopyBufferToImage(upload, staging.handle(), r.runSource.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &whole);
    imageBarrier(upload, r.runSource.handle(), 0, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                 VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                 VK_ACCESS_SHADER_READ_BIT);
    f.submission->submitAndWait(upload);
    f.submission->release(upload);
    return shift;
}

// The computed levels of the set's output cube, read back in the output format (the others empty).
CubeLevels readBackRunOutput(Filter::Impl& f, const Recording& r) {
    const FilterSettings& s = f.settings;
    const uint32_t bytesPerTexel = texelBytes(s.outputFormat);
    std::vector<VkBufferImageCopy> regions;
    VkDeviceSize offset = 0;
    for (int m : f.plan.computedLevels) {
        VkBufferImageCopy region{};
        region.bufferOffset = offset;
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), 0, kFaceCount};
        region.imageExtent = {uint32_t(s.faceSize >> m), uint32_t(s.faceSize >> m), 1};
        regions.push_back(region);
        offset += texelCount(s.faceSize >> m) * bytesPerTexel;
    }
    Buffer readBack(f.device, offset, Buffer::Kind::staging);
    VkCommandBuffer download = f.submission->begin();
    vkCmdCopyImageToBuffer(download, r.runOutput.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readBack.handle(),
                           uint32_t(regions.size()), regions.data());
    hostReadBarrier(download);
    f.submission->submitAndWait(download);
    f.submission->release(download);
    CubeLevels result(s.levelCount);
    for (std::size_t k = 0; k < f.plan.computedLevels.size(); ++k) {
        CubeImage& level = result[f.plan.computedLevels[k]];
        level.size = s.faceSize >> f.plan.computedLevels[k];
        level.rgb.clear();
        unpackTexels(static_cast<const unsigned char*>(readBack.mapped()) + regions[k].bufferOffset, texelCount(level.size), s.outputFormat,
                     level.rgb);
    }
    return result;
}

// Checks the probe, makes the set's run images, uploads the probe and binds them to the set (then
// current); returns the shift uploadRunSource applied.
int startRun(Filter::Impl& f, Recording& r, const CubeImage& source) {
    if (source.size != f.settings.faceSize)
        throw ProbeError(fmt::format("filter: the probe has face size {}, the filter was built for {}", source.size, f.settings.faceSize));
    makeRunImages(f, r);
    const int shift = uploadRunSource(f, r, source);
    f.current = &r;
    f.bindImages(r.runSourceView.handle(), r.runOutput.handle());
    return shift;
}

// A set for a run: the least recently used of those not in flight (the tools' runs complete before
// they return).
Recording& runSet(Filter::Impl& f) {
    f.acquire();
    f.batched = false;
    return *f.current;
}

// The run's output cube as an engine's would be laid out: made writable by the passes before them,
// and readable by the read-back after them.
VkImageLayout runOutputLayout(const Filter::Impl& f) {
    return f.plan.convertOutput ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_GENERAL;
}
void runOutputBeforePasses(const Filter::Impl& f, const Recording& r, VkCommandBuffer commandBuffer) {
    imageBarrier(commandBuffer, r.runOutput.handle(), 0, uint32_t(f.settings.levelCount), VK_IMAGE_LAYOUT_UNDEFINED, runOutputLayout(f),
                 VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
}
void runOutputAfterPasses(const Filter::Impl& f, const Recording& r, VkCommandBuffer commandBuffer) {
    imageBarrier(commandBuffer, r.runOutput.handle(), 0, uint32_t(f.settings.levelCount), runOutputLayout(f),
                 VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
}

// The set's levels read back and scaled back up by the run's shift.
CubeLevels finishRun(Filter::Impl& f, const Recording& r, int shift) {
    CubeLevels result = readBackRunOutput(f, r);
    shiftLevels(result, shift);
    if (shift != 0 && f.settings.outputFormat != VK_FORMAT_R32G32B32A32_SFLOAT) saturateTexels(result, f.settings.outputFormat);
    return result;
}

} // namespace

CubeLevels Filter::run(const CubeImage& source, int repeat, Timestamps timestamps) {
    Impl& f = *impl_;
    checkRepeat(repeat);
    Recording& r = runSet(f);
    const int shift = startRun(f, r, source);
    // The passes, recorded once and submitted `repeat` times.
    VkCommandBuffer passes = f.submission->begin();
    runOutputBeforePasses(f, r, passes);
    f.recordPasses(passes, timestamps);
    runOutputAfterPasses(f, r, passes);
    vkCheck(vkEndCommandBuffer(passes), "vkEndCommandBuffer");
    r.timer->clear();
    for (int k = 0; k < repeat; ++k) {
        f.submission->submitAndWait(passes, false);
        if (r.timed) r.timer->collect();
    }
    f.submission->release(passes);
    return finishRun(f, r, shift);
}

CubeLevels Filter::run(const CubeImage& source, const std::vector<Slice>& slices, std::vector<double>& sliceMs) {
    Impl& f = *impl_;
    if (slices.empty()) throw ProbeError("filter: no slices to run");
    Recording& r = runSet(f);
    const int shift = startRun(f, r, source);
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
    return finishRun(f, r, shift);
}

std::vector<CubeLevels> Filter::run(const std::vector<CubeImage>& sources, int repeat) {
    Impl& f = *impl_;
    checkRepeat(repeat);
    if (sources.empty() || sources.size() > std::size_t(f.settings.inFlight))
        throw ParameterError("inFlight",
                             fmt::format("a batch of {} probes runs with 1 to inFlight = {} probes", sources.size(), f.settings.inFlight));
    while (f.recordings.size() < sources.size()) f.recordings.push_back(f.makeRecording());
    std::vector<int> shifts;
    for (std::size_t p = 0; p < sources.size(); ++p) shifts.push_back(startRun(f, *f.recordings[p], sources[p]));
    // Every probe in its own set, one after another in one command buffer, timed as a whole.
    VkCommandBuffer passes = f.submission->begin();
    f.batchTimer->reset(passes);
    f.batchTimer->boundary(passes, 0);
    std::vector<Dispatch> dispatches;
    int barriers = 0;
    for (std::size_t p = 0; p < sources.size(); ++p) {
        Recording& r = *f.recordings[p];
        f.current = &r;
        runOutputBeforePasses(f, r, passes);
        f.recordPasses(passes, Timestamps::none);
        runOutputAfterPasses(f, r, passes);
        dispatches.insert(dispatches.end(), f.dispatches.begin(), f.dispatches.end());
        barriers += f.barriers;
    }
    f.batchTimer->boundary(passes, 1);
    vkCheck(vkEndCommandBuffer(passes), "vkEndCommandBuffer");
    f.batchTimer->clear();
    for (int k = 0; k < repeat; ++k) {
        f.submission->submitAndWait(passes, false);
        f.batchTimer->collect();
    }
    f.submission->release(passes);
    f.dispatches = std::move(dispatches);
    f.barriers = barriers;
    f.batched = true;
    std::vector<CubeLevels> levels;
    for (std::size_t p = 0; p < sources.size(); ++p) levels.push_back(finishRun(f, *f.recordings[p], shifts[p]));
    return levels;
}

CubeLevels Filter::downloadPyramid() const {
    Impl& f = *impl_;
    if (!f.plan.buildsPyramid) return {};
    const Recording& r = *f.current;
    if (f.plan.sampling == Sampling::exact) {
        std::vector<float> texels(r.pyramidBuffer.bytes() / sizeof(float));
        f.submission->download(r.pyramidBuffer, texels.data(), r.pyramidBuffer.bytes());
        return unpackPyramid(texels.data(), f.plan.pyramidOffsets, f.settings.faceSize, f.plan.pyramidDepth);
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
