// Pass 1, per pyramid level down to the depth, the source first (level 0):
// - exact sampling (shaders/pyramid.comp): each level of the bordered buffer, faces, edges and (by
//   the dispatch's last workgroup) border corners, down to face size
//   PROBE_PYRAMID_TAIL_SIZE, then (shaders/pyramid_tail.comp) the levels from there down, borders
//   and corners, in one workgroup; the reference builds level 0 alone, the source it reads texel by
//   texel (its corners unread);
// - hardware sampling: the mips of the pyramid cube image down to the tail, two a dispatch
//   (shaders/pyramid_tile.comp; from the source, mips 0 to 2) where two lie above the tail, else one
//   (shaders/pyramid_image.comp; from the source, mips 0 and 1), then the tail's mips in one
//   workgroup from face size PROBE_PYRAMID_TAIL_SIZE down, which saves the GPU a dispatch and a
//   barrier per small mip: where the device offers enough storage images, the last workgroup of the
//   last run's dispatch (shaders/pyramid_finish.glsl), else a dispatch of their own
//   (shaders/pyramid_tail.comp);
// then, for FIS on a dual-paraboloid map (shaders/paraboloid_map.comp), each level of the map from
// the bordered source, in windows where a level exceeds the storage-buffer range.
#include <algorithm>
#include <array>
#include <cstdint>

#include <paraboloid_map.spv.h>
#include <pyramid.spv.h>
#include <pyramid_batch.spv.h>
#include <pyramid_image_batch_rgba16f.spv.h>
#include <pyramid_image_batch_rgba32f.spv.h>
#include <pyramid_image_finish_batch_rgba16f.spv.h>
#include <pyramid_image_finish_batch_rgba32f.spv.h>
#include <pyramid_image_finish_rgba16f.spv.h>
#include <pyramid_image_finish_rgba32f.spv.h>
#include <pyramid_image_rgba16f.spv.h>
#include <pyramid_image_rgba32f.spv.h>
#include <pyramid_tail_batch_rgba16f.spv.h>
#include <pyramid_tail_batch_rgba32f.spv.h>
#include <pyramid_tail_exact.spv.h>
#include <pyramid_tail_rgba16f.spv.h>
#include <pyramid_tail_rgba32f.spv.h>
#include <pyramid_tile_batch_rgba16f.spv.h>
#include <pyramid_tile_batch_rgba32f.spv.h>
#include <pyramid_tile_finish_batch_rgba16f.spv.h>
#include <pyramid_tile_finish_batch_rgba32f.spv.h>
#include <pyramid_tile_finish_rgba16f.spv.h>
#include <pyramid_tile_finish_rgba32f.spv.h>
#include <pyramid_tile_rgba16f.spv.h>
#include <pyramid_tile_rgba32f.spv.h>

#include "device.h"
#include "filter_passes.h"
#include "probe/paraboloid.h"
#include "recording.h"

namespace probe::gpu {

namespace {

struct PyramidConstants {
    int32_t faceSize;
    int32_t level;
    int32_t tailLevel = 0; // the last run, where it builds the tail: its first mip, and the last
    int32_t lastLevel = 0;
};

struct PyramidWindowConstants {
    int32_t faceSize;
    int32_t level;
    int32_t firstFace; // the window's faces
    int32_t faceCount;
    uint32_t window; // its first texel
};

struct ParaboloidWindowConstants {
    int32_t faceSize;
    int32_t level;
    uint32_t start; // the level's texels the window holds
    uint32_t count;
    uint32_t window; // the window's first texel
};

struct PyramidTailConstants {
    int32_t faceSize;
    int32_t level;     // the first mip written
    int32_t lastLevel; // the last
    uint32_t window;   // exact sampling: the first texel of its window
};

// The tail's workgroup size (its constant_id 2): 256 lanes where the device allows.
int32_t tailLanes(const Device& device) {
    const VkPhysicalDeviceLimits& limits = device.impl().limits;
    return int32_t(std::min({256u, limits.maxComputeWorkGroupInvocations, limits.maxComputeWorkGroupSize[0]}));
}

} // namespace

PyramidPass::PyramidPass(const PassContext& context) : context_(context) {
    const FilterPlan& plan = context.plan;
    const PyramidSettings pyramid = context.settings.method.pyramid();
    // The shaders' kBoxKind and kInverseSolidAngle.
    const std::array<int32_t, 2> specialization{pyramid.kind == PyramidKind::box ? 1 : 0,
                                                pyramid.weighting == PyramidWeighting::inverseSolidAngle ? 1 : 0};
    const std::array<int32_t, 3> tailSpecialization{specialization[0], specialization[1], tailLanes(context.device)};
    if (plan.sampling == Sampling::hardware) {
        const bool half = plan.pyramidFormat == VK_FORMAT_R16G16B16A16_SFLOAT;
        const std::span<const uint32_t> spirv = half ? context.batchVariant(kPyramidImageRgba16fSpv, kPyramidImageBatchRgba16fSpv)
                                                     : context.batchVariant(kPyramidImageRgba32fSpv, kPyramidImageBatchRgba32fSpv);
        // The shaders' kFromSource: the first dispatch's mips 0 to 1 or 2.
        const std::array<int32_t, 3> fromSource{specialization[0], specialization[1], 1};
        const std::span<const uint32_t> tile = half ? context.batchVariant(kPyramidTileRgba16fSpv, kPyramidTileBatchRgba16fSpv)
                                                    : context.batchVariant(kPyramidTileRgba32fSpv, kPyramidTileBatchRgba32fSpv);
        // The pipelines of the runs, but a last run that builds the tail, which has its own.
        const std::size_t runs = plan.pyramidMipRuns.size() - (plan.pyramidTailInLastRun ? 1 : 0);
        for (std::size_t n = 0; n < runs; ++n) {
            const auto [first, count] = plan.pyramidMipRuns[n];
            if (first == 0 && count > 1) fromSource_ = context.pipeline(count == 3 ? tile : spirv, fromSource);
            else if (count == 2 && !pairs_) pairs_ = context.pipeline(tile, specialization);
            else if (count == 1 && !levels_) levels_ = context.pipeline(spirv, specialization);
        }
        if (plan.pyramidTailInLastRun) {
            const auto [first, count] = plan.pyramidMipRuns.back();
            const std::span<const uint32_t> lastSpirv =
                count == 3 || (first > 0 && count == 2)
                    ? (half ? context.batchVariant(kPyramidTileFinishRgba16fSpv, kPyramidTileFinishBatchRgba16fSpv)
                            : context.batchVariant(kPyramidTileFinishRgba32fSpv, kPyramidTileFinishBatchRgba32fSpv))
                    : (half ? context.batchVariant(kPyramidImageFinishRgba16fSpv, kPyramidImageFinishBatchRgba16fSpv)
                            : context.batchVariant(kPyramidImageFinishRgba32fSpv, kPyramidImageFinishBatchRgba32fSpv));
            // Its kFromSource, and its lanes: the tail's.
            const std::array<int32_t, 4> lastSpecialization{specialization[0], specialization[1], first == 0 && count > 1 ? 1 : 0,
                                                            tailLanes(context.device)};
            lastRun_ = context.pipeline(lastSpirv, lastSpecialization);
            return;
        }
        if (plan.pyramidTailLevel > 0)
            tail_ = context.pipeline(half ? context.batchVariant(kPyramidTailRgba16fSpv, kPyramidTailBatchRgba16fSpv)
                                          : context.batchVariant(kPyramidTailRgba32fSpv, kPyramidTailBatchRgba32fSpv),
                                     tailSpecialization);
        return;
    }
    levels_ = context.pipeline(context.batchVariant(kPyramidSpv, kPyramidBatchSpv), specialization);
    if (plan.pyramidTailLevel > 0) tail_ = context.pipeline(kPyramidTailExactSpv, tailSpecialization);
    if (plan.paraboloid) paraboloidMap_ = context.pipeline(kParaboloidMapSpv);
}

uint32_t PyramidPass::dispatchCount() const {
    const FilterPlan& plan = context_.plan;
    uint32_t count = 0;
    if (plan.sampling == Sampling::hardware) {
        count = uint32_t(plan.pyramidMipRuns.size()) + (tail_ ? 1 : 0);
    } else {
        // Each window a dispatch; the tail's one in all.
        count = uint32_t(plan.pyramidWindows.size());
    }
    if (paraboloidMap_) count += uint32_t(plan.paraboloidWindows.size());
    return count;
}

double PyramidPass::texelTaps() const {
    const FilterSettings& s = context_.settings;
    double taps = double(texelCount(s.faceSize)); // level 0: the source, one read a texel
    for (int level = 1; level <= (context_.plan.buildsPyramid ? context_.plan.pyramidDepth : 0); ++level)
        taps += 4.0 * double(texelCount(s.faceSize >> level));
    if (paraboloidMap_)
        for (int size = paraboloidSize(s.faceSize); size >= 1; size /= 2) taps += 4.0 * 2.0 * size * size;
    return taps * s.batchSize;
}

// Exact sampling: each level's windows (FilterPlan::pyramidWindows), every texel of their faces with
// the border and its corners; the tail's levels in one dispatch, a workgroup per cube. A level split into windows (a device whose
// storage-buffer range is smaller than the level) costs a dispatch and a barrier more per window.
void PyramidPass::recordBorderedLevels(const PassRecorder& recorder, const Recording& recording) const {
    const FilterSettings& s = context_.settings;
    const std::vector<PyramidWindow>& windows = context_.plan.pyramidWindows;
    for (std::size_t first = 0, end = 0; first < windows.size(); first = end) {
        const int level = windows[first].level;
        for (end = first; end < windows.size() && windows[end].level == level;) ++end;
        if (level > 0) recorder.barrier();
        if (tail_ && level == context_.plan.pyramidTailLevel) {
            recorder.bind(recording.pyramidSets[first]);
            const PyramidTailConstants constants{s.faceSize, level, context_.plan.pyramidDepth, uint32_t(windows[first].first)};
            recorder.dispatch(*tail_, "pyramid", level, constants, 1, uint32_t(s.batchSize));
            continue;
        }
        const std::size_t perFace = pyramidLevelTexels(s.faceSize >> level) / kFaceCount;
        for (std::size_t w = first; w < end; ++w) {
            // The windows of a level write apart, but each binds the whole buffer for reading.
            if (w > first) recorder.barrier();
            const PyramidWindow& window = windows[w];
            recorder.bind(recording.pyramidSets[w]);
            const PyramidWindowConstants constants{s.faceSize, level, window.firstFace, window.faceCount, uint32_t(window.first)};
            recorder.dispatch(*levels_, "pyramid", level, constants, groupsFor(perFace * window.faceCount));
        }
    }
}

// Hardware sampling: the mips of the pyramid image in the plan's runs (FilterPlan::pyramidMipRuns:
// one, two or, from the source, three mips a dispatch), the tail's in one workgroup, of the last run's
// dispatch or of its own; a layer of workgroups per cube of a batch.
void PyramidPass::recordMips(const PassRecorder& recorder, const Recording& recording) const {
    const FilterSettings& s = context_.settings;
    const FilterPlan& plan = context_.plan;
    const auto cubes = uint32_t(s.batchSize);
    const int depth = plan.buildsPyramid ? plan.pyramidDepth : 0;
    // A workgroup per 8x8 tile of mip k (pyramid_tile.comp).
    const auto tilesOf = [&](int k) { return uint32_t(texelCount(s.faceSize >> k) / 64); };
    for (const auto& [first, count] : plan.pyramidMipRuns) {
        if (first > 0) recorder.barrier();
        recorder.bind(recording.pyramidSets[first]);
        const bool last = lastRun_ && first == plan.pyramidMipRuns.back().first;
        const ComputePipeline& pipeline = last ? *lastRun_ : count == 1 ? *levels_ : first == 0 ? *fromSource_ : *pairs_;
        PyramidConstants constants{s.faceSize, first};
        if (last) {
            constants.tailLevel = plan.pyramidTailLevel;
            constants.lastLevel = depth;
        }
        const int mips = last ? depth - first + 1 : count;
        // An invocation per texel: of workgroups of the tail's lanes in the last run.
        const auto perTexel = [&](std::size_t texels) {
            const std::size_t lanes = last ? std::size_t(tailLanes(context_.device)) : kWorkgroupSize;
            return uint32_t((texels + lanes - 1) / lanes);
        };
        if (count == 1) {
            recorder.dispatch(pipeline, "pyramid", first, constants, perTexel(texelCount(s.faceSize >> first)), cubes, mips);
        } else if (first == 0 && count == 2) { // an invocation per texel of both
            recorder.dispatch(pipeline, "pyramid", 0, constants, perTexel(texelCount(s.faceSize) + texelCount(s.faceSize >> 1)), cubes,
                              mips);
        } else if (first == 0) { // mip 1 from the source, and mip 2 in tiles
            constants.level = 1;
            recorder.dispatch(pipeline, "pyramid", 0, constants, tilesOf(2), cubes, mips);
        } else {
            recorder.dispatch(pipeline, "pyramid", first, constants, tilesOf(first + 1), cubes, mips);
        }
    }
    if (tail_) {
        recorder.barrier();
        recorder.bind(recording.pyramidSets[plan.pyramidTailLevel]);
        const PyramidTailConstants constants{s.faceSize, plan.pyramidTailLevel, depth, 0};
        recorder.dispatch(*tail_, "pyramid", plan.pyramidTailLevel, constants, 1, cubes);
    }
}

void PyramidPass::record(const PassRecorder& recorder, const Recording& recording) const {
    const FilterSettings& s = context_.settings;
    if (context_.plan.sampling == Sampling::exact) recordBorderedLevels(recorder, recording);
    else recordMips(recorder, recording);
    if (!paraboloidMap_) return;
    // A barrier before each window: each reads the level above, and binds the whole buffer for it.
    const std::vector<ParaboloidWindow>& windows = context_.plan.paraboloidWindows;
    for (std::size_t w = 0; w < windows.size(); ++w) {
        recorder.barrier();
        recorder.bind(recording.pyramidSets[context_.plan.pyramidWindows.size() + w]);
        const ParaboloidWindowConstants constants{s.faceSize, windows[w].level, uint32_t(windows[w].start), uint32_t(windows[w].count),
                                                  uint32_t(windows[w].first)};
        recorder.dispatch(*paraboloidMap_, "pyramid", windows[w].level, constants, groupsFor(windows[w].count));
    }
}

} // namespace probe::gpu
