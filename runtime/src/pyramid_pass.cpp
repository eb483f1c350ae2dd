// Pass 1 (shaders/pyramid.comp): one dispatch per pyramid level down to the depth, each from the
// level before it.
#include <cstdint>

#include <pyramid.spv.h>

#include "filter_impl.h"

namespace probe::gpu {

namespace {

struct PyramidConstants {
    int32_t baseSize;
    int32_t fineLevel;
    int32_t boxKind;
    int32_t inverseSolidAngle;
};

} // namespace

std::span<const uint32_t> pyramidSpirv() { return kPyramidSpv; }

void recordPyramidPass(Filter::Impl& impl, VkCommandBuffer commandBuffer) {
    const FilterSettings& s = impl.settings;
    for (int fine = 0; fine < impl.pyramidDepth; ++fine) {
        if (fine > 0) computeBarrier(commandBuffer);
        const PyramidConstants constants{s.faceSize, fine, s.pyramid.kind == PyramidKind::box ? 1 : 0,
                                         s.pyramid.weighting == PyramidWeighting::inverseSolidAngle ? 1 : 0};
        dispatchPass(impl, commandBuffer, *impl.pass1, "pyramid", fine + 1, constants, groupsFor(texelCount(s.faceSize >> (fine + 1))));
    }
}

} // namespace probe::gpu
