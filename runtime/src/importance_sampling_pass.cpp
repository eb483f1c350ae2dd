// Filtered importance sampling (shaders/importance_sampling.comp): every level's samples, made by
// probecore in the tangent frame, in the table buffer, and one dispatch per output level computed,
// reading the cube pyramid or the dual-paraboloid map.
#include <cstdint>

#include <importance_sampling_exact_b10g11r11.spv.h>
#include <importance_sampling_exact_rgba16f.spv.h>
#include <importance_sampling_exact_rgba32f.spv.h>
#include <importance_sampling_hardware_b10g11r11.spv.h>
#include <importance_sampling_hardware_rgba16f.spv.h>
#include <importance_sampling_hardware_rgba32f.spv.h>
#include <importance_sampling_paraboloid_b10g11r11.spv.h>
#include <importance_sampling_paraboloid_rgba16f.spv.h>
#include <importance_sampling_paraboloid_rgba32f.spv.h>

#include "filter_impl.h"
#include "probe/importance_sampling.h"

namespace probe::gpu {

namespace {

struct ImportanceSamplingConstants {
    int32_t baseSize;
    int32_t pyramidLevels;
    int32_t level;
    uint32_t firstTexel;
    uint32_t endTexel;
    uint32_t firstSample;
    uint32_t sampleCount;
};

} // namespace

std::unique_ptr<ComputePipeline> makeImportanceSamplingPipeline(const Filter::Impl& impl) {
    const std::span<const uint32_t> spirv =
        impl.paraboloid ? outputVariant(impl, {kImportanceSamplingParaboloidRgba32fSpv, kImportanceSamplingParaboloidRgba16fSpv,
                                               kImportanceSamplingParaboloidB10g11r11Spv})
        : impl.sampling == Sampling::hardware
            ? outputVariant(impl, {kImportanceSamplingHardwareRgba32fSpv, kImportanceSamplingHardwareRgba16fSpv,
                                   kImportanceSamplingHardwareB10g11r11Spv})
            : outputVariant(impl,
                            {kImportanceSamplingExactRgba32fSpv, kImportanceSamplingExactRgba16fSpv, kImportanceSamplingExactB10g11r11Spv});
    return impl.pipeline(spirv);
}

std::vector<float> importanceSamplingBufferData(const FilterSettings& s, std::vector<uint32_t>& sampleOffsets) {
    std::vector<float> data;
    sampleOffsets = {0};
    for (const std::vector<Tap>& level : importanceSamplesPerLevel(s.faceSize, s.levelCount, s.mapping, s.method.fis)) {
        for (const Tap& sample : level)
            data.insert(data.end(), {static_cast<float>(sample.direction.x), static_cast<float>(sample.direction.y),
                                     static_cast<float>(sample.direction.z), static_cast<float>(sample.level)});
        sampleOffsets.push_back(sampleOffsets.back() + static_cast<uint32_t>(level.size()));
    }
    if (data.empty()) data.assign(4, 0.0f); // every level a copy: a buffer cannot be empty
    return data;
}

void recordImportanceSamplingLevel(Filter::Impl& impl, VkCommandBuffer commandBuffer, int m) {
    const FilterSettings& s = impl.settings;
    const uint32_t firstSample = impl.sampleOffsets[m];
    const ImportanceSamplingConstants constants{s.faceSize,
                                                impl.pyramidDepth + 1,
                                                m,
                                                impl.outputOffsets[m],
                                                impl.outputOffsets[m + 1],
                                                firstSample,
                                                impl.sampleOffsets[m + 1] - firstSample};
    dispatchPass(impl, commandBuffer, *impl.pass2, "fis", m, constants, groupsFor(impl.outputOffsets[m + 1] - impl.outputOffsets[m]));
}

} // namespace probe::gpu
