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

#include "filter_impl.h"
#include "probe/fis.h"

namespace probe::gpu {

namespace {

struct FisConstants {
    int32_t faceSize;
    int32_t pyramidLevels;
    int32_t firstLevel;
    std::array<uint32_t, kWrittenMipCount> groupEnd;
    std::array<uint32_t, kWrittenMipCount + 1> firstSample;
};

} // namespace

std::unique_ptr<ComputePipeline> makeFisPipeline(const Filter::Impl& impl) {
    const std::span<const uint32_t> spirv =
        impl.plan.paraboloid ? outputVariant(impl, {kFisParaboloidRgba32fSpv, kFisParaboloidRgba16fSpv, kFisParaboloidB10g11r11Spv})
        : impl.plan.sampling == Sampling::hardware
            ? impl.batchVariant(
                  outputVariant(impl, {kFisHardwareRgba32fSpv, kFisHardwareRgba16fSpv, kFisHardwareB10g11r11Spv}),
                  outputVariant(impl, {kFisHardwareBatchRgba32fSpv, kFisHardwareBatchRgba16fSpv, kFisHardwareBatchB10g11r11Spv}))
            : outputVariant(impl, {kFisExactRgba32fSpv, kFisExactRgba16fSpv, kFisExactB10g11r11Spv});
    return impl.pipeline(spirv);
}

void appendFisSamples(const std::vector<std::vector<Tap>>& perLevel, std::vector<float>& data, std::vector<uint32_t>& sampleOffsets) {
    sampleOffsets = {static_cast<uint32_t>(data.size() / 4)};
    for (const std::vector<Tap>& level : perLevel) {
        for (const Tap& sample : level)
            data.insert(data.end(), {static_cast<float>(sample.direction.x), static_cast<float>(sample.direction.y),
                                     static_cast<float>(sample.direction.z), static_cast<float>(sample.level)});
        sampleOffsets.push_back(sampleOffsets.back() + static_cast<uint32_t>(level.size()));
    }
}

void recordFisLevels(Filter::Impl& impl, VkCommandBuffer commandBuffer, std::span<const int> levels) {
    const FilterSettings& s = impl.settings;
    const auto groupsOf = [&](int m) { return groupsFor(impl.plan.outputOffsets[m + 1] - impl.plan.outputOffsets[m]); };
    FisConstants constants{s.faceSize, impl.plan.pyramidDepth + 1, levels.front(), levelGroupEnds(levels, groupsOf), {}};
    // Level levels[k]'s samples end where the next level's start (the groups' levels are consecutive).
    for (std::size_t k = 0; k < constants.firstSample.size(); ++k)
        constants.firstSample[k] = impl.sampleOffsets[std::size_t(levels.front()) + std::min(k, levels.size())];
    // A table's level handed to FIS runs the Filter's FIS pipeline beside the table's.
    const ComputePipeline& pipeline = impl.settings.method.kind == MethodKind::table ? *impl.handOff : *impl.pass2;
    dispatchPass(impl, commandBuffer, pipeline, "fis", levels.front(), constants, constants.groupEnd.back(), uint32_t(s.batchSize),
                 int(levels.size()));
}

} // namespace probe::gpu
