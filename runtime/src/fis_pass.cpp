// Filtered importance sampling (shaders/fis.comp): every level's samples, made by
// probecore in the tangent frame, in the table buffer, and one dispatch per group of output levels
// (FilterPlan::levelGroups), reading the cube pyramid or the dual-paraboloid map.
#include <algorithm>
#include <array>
#include <cstdint>

#include <fis_exact_b10g11r11.spv.h>
#include <fis_exact_rgba16f.spv.h>
#include <fis_exact_rgba32f.spv.h>
#include <fis_hardware_b10g11r11.spv.h>
#include <fis_hardware_batch_b10g11r11.spv.h>
#include <fis_hardware_batch_rgba16f.spv.h>
#include <fis_hardware_batch_rgba32f.spv.h>
#include <fis_hardware_rgba16f.spv.h>
#include <fis_hardware_rgba32f.spv.h>
#include <fis_paraboloid_b10g11r11.spv.h>
#include <fis_paraboloid_rgba16f.spv.h>
#include <fis_paraboloid_rgba32f.spv.h>
#include <fis_wide_exact_b10g11r11.spv.h>
#include <fis_wide_exact_rgba16f.spv.h>
#include <fis_wide_exact_rgba32f.spv.h>
#include <fis_wide_hardware_b10g11r11.spv.h>
#include <fis_wide_hardware_batch_b10g11r11.spv.h>
#include <fis_wide_hardware_batch_rgba16f.spv.h>
#include <fis_wide_hardware_batch_rgba32f.spv.h>
#include <fis_wide_hardware_rgba16f.spv.h>
#include <fis_wide_hardware_rgba32f.spv.h>
#include <fis_wide_paraboloid_b10g11r11.spv.h>
#include <fis_wide_paraboloid_rgba16f.spv.h>
#include <fis_wide_paraboloid_rgba32f.spv.h>

#include "filter_passes.h"
#include "probe/fis.h"

namespace probe::gpu {

namespace {

struct FisConstants {
    int32_t faceSize;
    int32_t pyramidLevels;
    int32_t firstLevel;
    std::array<uint32_t, kWideWrittenMipCount> groupEnd; // shaders/fis.comp's PROBE_MAX_GROUP_LEVELS
    std::array<uint32_t, kWideWrittenMipCount + 1> firstSample;
};

} // namespace

FisPass::FisPass(const PassContext& context, std::vector<uint32_t> sampleOffsets)
    : context_(context), sampleOffsets_(std::move(sampleOffsets)) {
    const std::span<const uint32_t> spirv =
        context.plan.paraboloid
            ? context.groupVariant({kFisParaboloidRgba32fSpv, kFisParaboloidRgba16fSpv, kFisParaboloidB10g11r11Spv},
                                   {kFisWideParaboloidRgba32fSpv, kFisWideParaboloidRgba16fSpv, kFisWideParaboloidB10g11r11Spv})
        : context.plan.sampling == Sampling::hardware
            ? context.batchVariant(
                  context.groupVariant({kFisHardwareRgba32fSpv, kFisHardwareRgba16fSpv, kFisHardwareB10g11r11Spv},
                                       {kFisWideHardwareRgba32fSpv, kFisWideHardwareRgba16fSpv, kFisWideHardwareB10g11r11Spv}),
                  context.groupVariant(
                      {kFisHardwareBatchRgba32fSpv, kFisHardwareBatchRgba16fSpv, kFisHardwareBatchB10g11r11Spv},
                      {kFisWideHardwareBatchRgba32fSpv, kFisWideHardwareBatchRgba16fSpv, kFisWideHardwareBatchB10g11r11Spv}))
            : context.groupVariant({kFisExactRgba32fSpv, kFisExactRgba16fSpv, kFisExactB10g11r11Spv},
                                   {kFisWideExactRgba32fSpv, kFisWideExactRgba16fSpv, kFisWideExactB10g11r11Spv});
    pipeline_ = context.pipeline(spirv);
}

std::vector<uint32_t> appendFisSamples(const std::vector<std::vector<Tap>>& perLevel, std::vector<float>& data) {
    std::vector<uint32_t> sampleOffsets{static_cast<uint32_t>(data.size() / 4)};
    for (const std::vector<Tap>& level : perLevel) {
        for (const Tap& sample : level)
            data.insert(data.end(), {static_cast<float>(sample.direction.x), static_cast<float>(sample.direction.y),
                                     static_cast<float>(sample.direction.z), static_cast<float>(sample.level)});
        sampleOffsets.push_back(sampleOffsets.back() + static_cast<uint32_t>(level.size()));
    }
    return sampleOffsets;
}

void FisPass::record(const PassRecorder& recorder, std::span<const int> levels) const {
    const FilterSettings& s = context_.settings;
    const FilterPlan& plan = context_.plan;
    const auto groupsOf = [&](int m) { return groupsFor(plan.outputOffsets[m + 1] - plan.outputOffsets[m]); };
    FisConstants constants{s.faceSize, plan.pyramidDepth + 1, levels.front(), levelGroupEnds(levels, groupsOf), {}};
    // Level levels[k]'s samples end where the next level's start (the groups' levels are consecutive).
    for (std::size_t k = 0; k < constants.firstSample.size(); ++k)
        constants.firstSample[k] = sampleOffsets_[std::size_t(levels.front()) + std::min(k, levels.size())];
    recorder.dispatch(*pipeline_, "fis", levels.front(), constants, constants.groupEnd.back(), uint32_t(s.batchSize), int(levels.size()));
}

} // namespace probe::gpu
