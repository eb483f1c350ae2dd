// Pass 2 at the output levels with alpha = 0 (shaders/copy_level.comp), for every method: a copy of
// the source, dispatched under the method's pass name so that a run lists one dispatch per level.
#include <cstdint>

#include <copy_level.spv.h>

#include "filter_impl.h"

namespace probe::gpu {

namespace {

struct CopyLevelConstants {
    int32_t baseSize;
    uint32_t firstTexel;
    uint32_t endTexel;
};

} // namespace

std::span<const uint32_t> copyLevelSpirv() { return kCopyLevelSpv; }

void recordCopyLevel(Filter::Impl& impl, VkCommandBuffer commandBuffer, int level) {
    const CopyLevelConstants constants{impl.settings.faceSize, impl.outputOffsets[level], impl.outputOffsets[level + 1]};
    dispatchPass(impl, commandBuffer, *impl.copy, methodName(impl.settings.method), level, constants,
                 groupsFor(impl.outputOffsets[level + 1] - impl.outputOffsets[level]));
}

} // namespace probe::gpu
