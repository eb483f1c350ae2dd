// Pass 1 (shaders/pyramid.comp, then shaders/pyramid_corners.comp): per pyramid level, one dispatch for
// its faces and edges and one for its border corners, down to the depth:
// level 0's border, then each level from the one before it.
#include <cstdint>

#include <pyramid.spv.h>
#include <pyramid_corners.spv.h>

#include "filter_impl.h"

namespace probe::gpu {

namespace {

struct PyramidConstants {
    int32_t baseSize;
    int32_t level;
};

} // namespace

std::span<const uint32_t> pyramidSpirv() { return kPyramidSpv; }
std::span<const uint32_t> pyramidCornersSpirv() { return kPyramidCornersSpv; }

std::array<int32_t, 2> pyramidSpecialization(const PyramidSettings& pyramid) {
    return {pyramid.kind == PyramidKind::box ? 1 : 0, pyramid.weighting == PyramidWeighting::inverseSolidAngle ? 1 : 0};
}

void recordPyramidPass(Filter::Impl& impl, VkCommandBuffer commandBuffer) {
    const FilterSettings& s = impl.settings;
    for (int level = 0; level <= impl.pyramidDepth; ++level) {
        if (level > 0) computeBarrier(commandBuffer);
        const PyramidConstants constants{s.faceSize, level};
        // Level 0: the border rings of 4 S + 4 texels per face; the others: every texel with its border.
        const int size = s.faceSize >> level;
        const std::size_t texels = level == 0 ? std::size_t(kFaceCount) * (4 * size + 4) : pyramidLevelTexels(size);
        dispatchPass(impl, commandBuffer, *impl.pass1, "pyramid", level, constants, groupsFor(texels));
        computeBarrier(commandBuffer);
        dispatchPass(impl, commandBuffer, *impl.pass1Corners, "pyramid", level, constants, groupsFor(kFaceCount * 4));
    }
}

} // namespace probe::gpu
