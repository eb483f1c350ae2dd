// Pass 2 at the output levels with alpha = 0 (shaders/copy_level.comp), for every method: a copy of
// the source, dispatched under the method's pass name so that a run lists one dispatch per level.
#include <cstdint>

#include <copy_level_b10g11r11.spv.h>
#include <copy_level_batch_b10g11r11.spv.h>
#include <copy_level_batch_rgba16f.spv.h>
#include <copy_level_batch_rgba32f.spv.h>
#include <copy_level_rgba16f.spv.h>
#include <copy_level_rgba32f.spv.h>

#include "filter_passes.h"

namespace probe::gpu {

namespace {

struct CopyLevelConstants {
    int32_t faceSize;
    int32_t level;
    uint32_t firstTexel;
    uint32_t endTexel;
};

} // namespace

CopyLevelPass::CopyLevelPass(const PassContext& context) : context_(context) {
    pipeline_ = context.pipeline(
        context.batchVariant(context.outputVariant({kCopyLevelRgba32fSpv, kCopyLevelRgba16fSpv, kCopyLevelB10g11r11Spv}),
                             context.outputVariant({kCopyLevelBatchRgba32fSpv, kCopyLevelBatchRgba16fSpv, kCopyLevelBatchB10g11r11Spv})));
}

void CopyLevelPass::record(const PassRecorder& recorder, int level) const {
    const FilterPlan& plan = context_.plan;
    const CopyLevelConstants constants{context_.settings.faceSize, level, plan.outputOffsets[level], plan.outputOffsets[level + 1]};
    recorder.dispatch(*pipeline_, methodKindName(context_.settings.method.kind), level, constants,
                      groupsFor(plan.outputOffsets[level + 1] - plan.outputOffsets[level]), uint32_t(context_.settings.batchSize));
}

} // namespace probe::gpu
