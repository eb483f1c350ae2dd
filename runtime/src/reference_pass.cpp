// The exact reference on the GPU (shaders/reference.comp): one dispatch per output level computed.
#include <cstdint>

#include <reference.spv.h>

#include "filter_impl.h"

namespace probe::gpu {

namespace {

struct ReferenceConstants {
    int32_t sourceSize;
    int32_t outLevel;
    float alpha2;
};

} // namespace

std::span<const uint32_t> referenceSpirv() { return kReferenceSpv; }

void recordReferenceLevel(Filter::Impl& impl, VkCommandBuffer commandBuffer, int m) {
    const FilterSettings& s = impl.settings;
    const double alpha = levelAlpha(s.mapping, m, s.levelCount);
    const ReferenceConstants constants{s.faceSize, m, static_cast<float>(alpha * alpha)};
    dispatchPass(impl, commandBuffer, *impl.pass2, "reference", m, constants, groupsFor(texelCount(s.faceSize >> m)));
}

} // namespace probe::gpu
