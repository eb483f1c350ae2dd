// Filtered importance sampling (shaders/importance_sampling.comp): alpha^2 and the sample count per
// level in the table buffer and one dispatch for all output levels (or one per level computed).
#include <cstdint>
#include <numbers>

#include <fmt/format.h>
#include <importance_sampling.spv.h>

#include "filter_impl.h"
#include "probe/error.h"
#include "probe/importance_sampling.h"

namespace probe::gpu {

namespace {

struct ImportanceSamplingConstants {
    int32_t baseSize;
    int32_t pyramidLevels;
    int32_t levelCount;
    float bias;
    float texelSolidAngle;
    uint32_t copyLevels;
    uint32_t firstTexel;
    uint32_t endTexel;
};

} // namespace

std::span<const uint32_t> importanceSamplingSpirv() { return kImportanceSamplingSpv; }

std::vector<float> importanceSamplingBufferData(const FilterSettings& s) {
    ImportanceSamplingSettings counts;
    counts.samples = s.fisSamples;
    counts.levelSamples = s.fisLevelSamples;
    validateSampleCounts(counts, s.levelCount);
    std::vector<float> data;
    for (int m = 0; m < s.levelCount; ++m) {
        const double alpha = levelAlpha(s.mapping, m, s.levelCount);
        data.insert(data.end(), {static_cast<float>(alpha * alpha), static_cast<float>(counts.samplesAt(m)), 0.0f, 0.0f});
    }
    return data;
}

void recordImportanceSamplingPass(Filter::Impl& impl, VkCommandBuffer commandBuffer) {
    const FilterSettings& s = impl.settings;
    const double texelSolidAngle = 4.0 * std::numbers::pi / (6.0 * s.faceSize * s.faceSize);
    for (const Filter::Impl::OutputRange& r : impl.outputRanges()) {
        const ImportanceSamplingConstants constants{s.faceSize, impl.pyramidLevels, s.levelCount, static_cast<float>(s.fisBias),
                                                    static_cast<float>(texelSolidAngle), impl.copyLevels, r.first, r.end};
        dispatchPass(impl, commandBuffer, *impl.pass2, "fis", r.level, constants, groupsFor(r.end - r.first));
    }
}

} // namespace probe::gpu
