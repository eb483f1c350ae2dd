// Pass 2 at the output levels with alpha = 0 (shaders/copy_level.comp), for every method: a copy of
// the source, dispatched under the method's pass name so that a run lists one dispatch per level.
#include <cstdint>

#include <copy_level_b10g11r11.spv.h>
#include <copy_level_batch_b10g11r11.spv.h>
#include <copy_level_batch_rgba16f.spv.h>
#include <copy_level_batch_rgba32f.spv.h>
#include <copy_level_rgba16f.spv.h>
#include <copy_level_rgba32f.spv.h>

#include "filter_impl.h"

namespace probe::gpu {

namespace {

struct CopyLevelConstants {
    int32_t faceSize;
    int32_t level;
    uint32_t firstTexel;
    uint32_t endTexel;
};

} // namespace

std::span<const uint32_t> outputVariant(const Filter::Impl& impl, std::array<std::span<const uint32_t>, 3> variants) {
    if (impl.plan.convertOutput) return variants[0];
    switch (impl.settings.outputFormat) {
    case VK_FORMAT_R16G16B16A16_SFLOAT: return variants[1];
    case VK_FORMAT_B10G11R11_UFLOAT_PACK32: return variants[2];
    default: return variants[0];
    }
}

std::unique_ptr<ComputePipeline> makeCopyLevelPipeline(const Filter::Impl& impl) {
    return impl.pipeline(
        impl.batchVariant(outputVariant(impl, {kCopyLevelRgba32fSpv, kCopyLevelRgba16fSpv, kCopyLevelB10g11r11Spv}),
                          outputVariant(impl, {kCopyLevelBatchRgba32fSpv, kCopyLevelBatchRgba16fSpv, kCopyLevelBatchB10g11r11Spv})));
}

void recordCopyLevel(Filter::Impl& impl, VkCommandBuffer commandBuffer, int level) {
    const CopyLevelConstants constants{impl.settings.faceSize, level, impl.plan.outputOffsets[level], impl.plan.outputOffsets[level + 1]};
    dispatchPass(impl, commandBuffer, *impl.copy, methodKindName(impl.settings.method.kind), level, constants,
                 groupsFor(impl.plan.outputOffsets[level + 1] - impl.plan.outputOffsets[level]), uint32_t(impl.settings.batchSize));
}

} // namespace probe::gpu
