// Pass 1, per pyramid level down to the depth, the source first (level 0):
// - exact sampling (shaders/pyramid.comp, then shaders/pyramid_corners.comp): each level of the
//   bordered buffer, faces and edges, then its border corners, down to face size
//   PROBE_PYRAMID_TAIL_SIZE, then (shaders/pyramid_tail.comp) the levels from there down, borders
//   and corners, in one workgroup; the reference builds level 0 alone, the source it reads texel by
//   texel, with no corners;
// - hardware sampling (shaders/pyramid_image.comp): each mip of the pyramid cube image down to face
//   size PROBE_PYRAMID_TAIL_SIZE (mips 0 and 1 in one dispatch, both from the source, where the tail
//   starts below mip 1), then (shaders/pyramid_tail.comp) the mips from there down in one workgroup,
//   which saves the GPU a dispatch and a barrier per small mip;
// then, for FIS on a dual-paraboloid map (shaders/paraboloid_map.comp), each level of the map from
// the bordered source.
#include <algorithm>
#include <array>
#include <cstdint>

#include <paraboloid_map.spv.h>
#include <pyramid.spv.h>
#include <pyramid_batch.spv.h>
#include <pyramid_corners.spv.h>
#include <pyramid_image_batch_rgba16f.spv.h>
#include <pyramid_image_batch_rgba32f.spv.h>
#include <pyramid_image_rgba16f.spv.h>
#include <pyramid_image_rgba32f.spv.h>
#include <pyramid_tail_batch_rgba16f.spv.h>
#include <pyramid_tail_batch_rgba32f.spv.h>
#include <pyramid_tail_exact.spv.h>
#include <pyramid_tail_rgba16f.spv.h>
#include <pyramid_tail_rgba32f.spv.h>

#include "device.h"
#include "filter_impl.h"
#include "probe/paraboloid.h"

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

struct PyramidTailConstants {
    int32_t faceSize;
    int32_t level;     // the first mip written
    int32_t lastLevel; // the last
    uint32_t window;   // exact sampling: the first texel of its window
};

// The tail's workgroup size (its constant_id 2): 256 lanes where the device allows.
int32_t tailLanes(const Filter::Impl& impl) {
    const VkPhysicalDeviceLimits& limits = impl.device.impl().limits;
    return int32_t(std::min({256u, limits.maxComputeWorkGroupInvocations, limits.maxComputeWorkGroupSize[0]}));
}

} // namespace

void makePyramidPipelines(Filter::Impl& impl) {
    const PyramidSettings pyramid = impl.settings.method.pyramid();
    // The shaders' kBoxKind and kInverseSolidAngle.
    const std::array<int32_t, 2> specialization{pyramid.kind == PyramidKind::box ? 1 : 0,
                                                pyramid.weighting == PyramidWeighting::inverseSolidAngle ? 1 : 0};
    if (impl.plan.sampling == Sampling::hardware) {
        const bool half = impl.plan.pyramidFormat == VK_FORMAT_R16G16B16A16_SFLOAT;
        const std::span<const uint32_t> spirv = half ? impl.batchVariant(kPyramidImageRgba16fSpv, kPyramidImageBatchRgba16fSpv)
                                                     : impl.batchVariant(kPyramidImageRgba32fSpv, kPyramidImageBatchRgba32fSpv);
        impl.pass1 = impl.pipeline(spirv, specialization);
        if (impl.plan.pyramidFromSource) // the shader's kFromSource
            impl.pass1Source = impl.pipeline(spirv, std::array<int32_t, 3>{specialization[0], specialization[1], 1});
        if (impl.plan.pyramidTailLevel > 0) {
            const std::array<int32_t, 3> tailSpecialization{specialization[0], specialization[1], tailLanes(impl)};
            impl.pass1Tail = impl.pipeline(half ? impl.batchVariant(kPyramidTailRgba16fSpv, kPyramidTailBatchRgba16fSpv)
                                                : impl.batchVariant(kPyramidTailRgba32fSpv, kPyramidTailBatchRgba32fSpv),
                                           tailSpecialization);
        }
        return;
    }
    impl.pass1 = impl.pipeline(impl.batchVariant(kPyramidSpv, kPyramidBatchSpv), specialization);
    if (impl.plan.buildsPyramid) impl.pass1Corners = impl.pipeline(kPyramidCornersSpv);
    if (impl.plan.pyramidTailLevel > 0)
        impl.pass1Tail = impl.pipeline(kPyramidTailExactSpv, std::array<int32_t, 3>{specialization[0], specialization[1], tailLanes(impl)});
    if (impl.plan.paraboloid) impl.paraboloidMap = impl.pipeline(kParaboloidMapSpv);
}

uint32_t pyramidDispatchCount(const Filter::Impl& impl) {
    uint32_t count = 0;
    if (impl.plan.sampling == Sampling::hardware) {
        const int depth = impl.plan.buildsPyramid ? impl.plan.pyramidDepth : 0;
        count =
            uint32_t((impl.pass1Tail ? impl.plan.pyramidTailLevel - 1 : depth) + 1) + (impl.pass1Tail ? 1 : 0) - (impl.pass1Source ? 1 : 0);
    } else {
        // Each window a dispatch, and one for its corners; the tail's one in all.
        count = uint32_t(impl.plan.pyramidWindows.size()) * (impl.pass1Corners ? 2 : 1) - (impl.pass1Tail ? 1 : 0);
    }
    if (impl.paraboloidMap)
        for (int level = 0; (paraboloidSize(impl.settings.faceSize) >> level) >= 1; ++level) ++count;
    return count;
}

double pyramidTexelTaps(const Filter::Impl& impl) {
    double taps = double(texelCount(impl.settings.faceSize)); // level 0: the source, one read a texel
    for (int level = 1; level <= (impl.plan.buildsPyramid ? impl.plan.pyramidDepth : 0); ++level)
        taps += 4.0 * double(texelCount(impl.settings.faceSize >> level));
    if (impl.paraboloidMap)
        for (int size = paraboloidSize(impl.settings.faceSize); size >= 1; size /= 2) taps += 4.0 * 2.0 * size * size;
    return taps * impl.settings.batchSize;
}

namespace {

// Exact sampling: each level's windows (FilterPlan::pyramidWindows), every texel of their faces with
// the border, then their faces' border corners; the tail's levels in one dispatch, a workgroup per
// cube. A level split into windows (a device whose storage-buffer range is smaller than the level)
// costs a dispatch and a barrier more per window.
void recordBorderedLevels(Filter::Impl& impl, VkCommandBuffer commandBuffer) {
    const std::vector<PyramidWindow>& windows = impl.plan.pyramidWindows;
    for (std::size_t first = 0, end = 0; first < windows.size(); first = end) {
        const int level = windows[first].level;
        for (end = first; end < windows.size() && windows[end].level == level;) ++end;
        if (level > 0) impl.barrier(commandBuffer);
        if (impl.pass1Tail && level == impl.plan.pyramidTailLevel) {
            impl.descriptors->bind(commandBuffer, impl.current->pyramidSets[first]);
            const PyramidTailConstants constants{impl.settings.faceSize, level, impl.plan.pyramidDepth, uint32_t(windows[first].first)};
            dispatchPass(impl, commandBuffer, *impl.pass1Tail, "pyramid", level, constants, 1, uint32_t(impl.settings.batchSize));
            continue;
        }
        const std::size_t perFace = pyramidLevelTexels(impl.settings.faceSize >> level) / kFaceCount;
        for (const bool corners : {false, true}) {
            if (corners && !impl.pass1Corners) break;
            if (corners) impl.barrier(commandBuffer);
            for (std::size_t w = first; w < end; ++w) {
                // The windows of a level write apart, but each binds the whole buffer for reading.
                if (w > first) impl.barrier(commandBuffer);
                const PyramidWindow& window = windows[w];
                impl.descriptors->bind(commandBuffer, impl.current->pyramidSets[w]);
                const PyramidWindowConstants constants{impl.settings.faceSize, level, window.firstFace, window.faceCount,
                                                       uint32_t(window.first)};
                const std::size_t texels = corners ? 4 * std::size_t(window.faceCount) : perFace * window.faceCount;
                dispatchPass(impl, commandBuffer, corners ? *impl.pass1Corners : *impl.pass1, "pyramid", level, constants,
                             groupsFor(texels));
            }
        }
    }
}

// Hardware sampling: each mip of the pyramid image (mips 0 and 1 in one dispatch where the plan says
// so), the tail's in one dispatch; a layer of workgroups per cube of a batch.
void recordPyramidMips(Filter::Impl& impl, VkCommandBuffer commandBuffer) {
    const FilterSettings& s = impl.settings;
    const auto cubes = uint32_t(s.batchSize);
    const int depth = impl.plan.buildsPyramid ? impl.plan.pyramidDepth : 0;
    const int lastSingle = impl.pass1Tail ? impl.plan.pyramidTailLevel - 1 : depth;
    int level = 0;
    if (impl.pass1Source) {
        impl.descriptors->bind(commandBuffer, impl.current->pyramidSets[0]);
        const PyramidConstants constants{s.faceSize, 0};
        const std::size_t texels = texelCount(s.faceSize) + texelCount(s.faceSize >> 1);
        dispatchPass(impl, commandBuffer, *impl.pass1Source, "pyramid", 0, constants, groupsFor(texels), cubes, 2);
        level = 2;
    }
    for (; level <= lastSingle; ++level) {
        if (level > 0) impl.barrier(commandBuffer);
        impl.descriptors->bind(commandBuffer, impl.current->pyramidSets[level]);
        const PyramidConstants constants{s.faceSize, level};
        dispatchPass(impl, commandBuffer, *impl.pass1, "pyramid", level, constants, groupsFor(texelCount(s.faceSize >> level)), cubes);
    }
    if (impl.pass1Tail) {
        impl.barrier(commandBuffer);
        impl.descriptors->bind(commandBuffer, impl.current->pyramidSets[impl.plan.pyramidTailLevel]);
        const PyramidTailConstants constants{s.faceSize, impl.plan.pyramidTailLevel, depth, 0};
        dispatchPass(impl, commandBuffer, *impl.pass1Tail, "pyramid", impl.plan.pyramidTailLevel, constants, 1, cubes);
    }
}

} // namespace

void recordPyramidPass(Filter::Impl& impl, VkCommandBuffer commandBuffer) {
    const FilterSettings& s = impl.settings;
    if (impl.plan.sampling == Sampling::exact) recordBorderedLevels(impl, commandBuffer);
    else recordPyramidMips(impl, commandBuffer);
    if (!impl.paraboloidMap) return;
    for (int level = 0; (paraboloidSize(s.faceSize) >> level) >= 1; ++level) {
        impl.barrier(commandBuffer);
        const PyramidConstants constants{s.faceSize, level};
        const std::size_t size = static_cast<std::size_t>(paraboloidSize(s.faceSize) >> level);
        dispatchPass(impl, commandBuffer, *impl.paraboloidMap, "pyramid", level, constants, groupsFor(2 * size * size));
    }
}

} // namespace probe::gpu
