// Pass 1, per pyramid level down to the depth, the source first (level 0):
// - exact sampling (shaders/pyramid.comp): each level of the bordered buffer, faces, edges and (by
//   the dispatch's last workgroup) border corners, down to face size
//   PROBE_PYRAMID_TAIL_SIZE, then (shaders/pyramid_tail.comp) the levels from there down, borders
//   and corners, in one workgroup; the reference builds level 0 alone, the source it reads texel by
//   texel (its corners unread);
// - hardware sampling: each mip of the pyramid cube image down to the tail in a dispatch of its own
//   (shaders/pyramid_image.comp), then the tail's mips in one workgroup from face size
//   PROBE_PYRAMID_TAIL_SIZE down (shaders/pyramid_tail.comp), which saves the GPU a dispatch and a
//   barrier per small mip. A dispatch a mip is what an H200 runs fastest: building two mips a dispatch
//   (the first over a ring of texels, kept in shared memory) or the tail in the last workgroup of the
//   dispatch above it trades parallelism and cached reads for a barrier, and loses
//   (docs/benchmarks.md, "Pass 1's dispatches");
// then, for FIS on a dual-paraboloid map (shaders/paraboloid_map.comp), each level of the map from
// the bordered source, in windows where a level exceeds the storage-buffer range.
#include <algorithm>
#include <array>
#include <cstdint>

#include <paraboloid_map.spv.h>
#include <pyramid.spv.h>
#include <pyramid_batch.spv.h>
#include <pyramid_image_batch_rgb9e5.spv.h>
#include <pyramid_image_batch_rgba16f.spv.h>
#include <pyramid_image_batch_rgba32f.spv.h>
#include <pyramid_image_rgb9e5.spv.h>
#include <pyramid_image_rgba16f.spv.h>
#include <pyramid_image_rgba32f.spv.h>
#include <pyramid_tail_batch_rgb9e5.spv.h>
#include <pyramid_tail_batch_rgba16f.spv.h>
#include <pyramid_tail_batch_rgba32f.spv.h>
#include <pyramid_tail_exact.spv.h>
#include <pyramid_tail_rgb9e5.spv.h>
#include <pyramid_tail_rgba16f.spv.h>
#include <pyramid_tail_rgba32f.spv.h>

#include "device.h"
#include "filter_passes.h"
#include "probe/paraboloid.h"
#include "recording.h"

namespace probe::gpu {

namespace {

struct PyramidConstants {
    int32_t faceSize;
    int32_t level;
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
        // The shaders of the pyramid's format: {mip, tail}, each for one probe and for a batch.
        const auto [image, tail] = [&]() -> std::pair<std::span<const uint32_t>, std::span<const uint32_t>> {
            switch (plan.pyramidFormat) {
            case VK_FORMAT_R16G16B16A16_SFLOAT:
                return {context.batchVariant(kPyramidImageRgba16fSpv, kPyramidImageBatchRgba16fSpv),
                        context.batchVariant(kPyramidTailRgba16fSpv, kPyramidTailBatchRgba16fSpv)};
            case VK_FORMAT_E5B9G9R9_UFLOAT_PACK32:
                return {context.batchVariant(kPyramidImageRgb9e5Spv, kPyramidImageBatchRgb9e5Spv),
                        context.batchVariant(kPyramidTailRgb9e5Spv, kPyramidTailBatchRgb9e5Spv)};
            default:
                return {context.batchVariant(kPyramidImageRgba32fSpv, kPyramidImageBatchRgba32fSpv),
                        context.batchVariant(kPyramidTailRgba32fSpv, kPyramidTailBatchRgba32fSpv)};
            }
        }();
        levels_ = context.pipeline(image, specialization);
        if (plan.pyramidTailLevel > 0) tail_ = context.pipeline(tail, tailSpecialization);
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
        // A dispatch a mip above the tail, and the tail's.
        count = tail_ ? uint32_t(plan.pyramidTailLevel) + 1 : uint32_t(plan.buildsPyramid ? plan.pyramidDepth : 0) + 1;
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
            recorder.dispatch(*tail_, "pyramid", level, constants, 1, uint32_t(s.batchSize), context_.plan.pyramidDepth - level + 1);
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

// Hardware sampling: each mip of the pyramid image above the tail a dispatch, then the tail's in one
// workgroup; a layer of workgroups per cube of a batch.
void PyramidPass::recordMips(const PassRecorder& recorder, const Recording& recording) const {
    const FilterSettings& s = context_.settings;
    const FilterPlan& plan = context_.plan;
    const auto cubes = uint32_t(s.batchSize);
    const int depth = plan.buildsPyramid ? plan.pyramidDepth : 0;
    const int lastSingle = tail_ ? plan.pyramidTailLevel - 1 : depth;
    for (int level = 0; level <= lastSingle; ++level) {
        if (level > 0) recorder.barrier();
        recorder.bind(recording.pyramidSets[level]);
        const PyramidConstants constants{s.faceSize, level};
        recorder.dispatch(*levels_, "pyramid", level, constants, groupsFor(texelCount(s.faceSize >> level)), cubes);
    }
    if (tail_) {
        recorder.barrier();
        recorder.bind(recording.pyramidSets[plan.pyramidTailLevel]);
        const PyramidTailConstants constants{s.faceSize, plan.pyramidTailLevel, depth, 0};
        recorder.dispatch(*tail_, "pyramid", plan.pyramidTailLevel, constants, 1, cubes, depth - plan.pyramidTailLevel + 1);
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
