// Pass 1 (shaders/pyramid.comp): one dispatch per pyramid level, with its border, down to the depth:
// level 0's border, then each level from the one before it.
#include <cstdint>

#include <pyramid.spv.h>

#include "filter_impl.h"

namespace probe::gpu {

namespace {

struct PyramidConstants {
    int32_t baseSize;
    int32_t level;
    int32_t boxKind;
    int32_t inverseSolidAngle;
};

} // namespace

std::span<const uint32_t> pyramidSpirv() { return kPyramidSpv; }

void recordPyramidPass(Filter::Impl& impl, VkCommandBuffer commandBuffer) {
    const FilterSettings& s = impl.settings;
    for (int level = 0; level <= impl.pyramidDepth; ++level) {
        if (level > 0) computeBarrier(commandBuffer);
        const PyramidConstants constants{s.faceSize, level, s.pyramid.kind == PyramidKind::box ? 1 : 0,
                                         s.pyramid.weighting == PyramidWeighting::inverseSolidAngle ? 1 : 0};
        const int size = s.faceSize >> level;
        dispatchPass(impl, commandBuffer, *impl.pass1, "pyramid", level, constants, groupsFor(kFaceCount * (level == 0 ? 4 * size + 4 : (size + 2) * (size + 2))));
    }
}

} // namespace probe::gpu
