// The exact reference on the GPU (shaders/reference.comp): per output level computed, one dispatch
// per chunk of source rows (at most kChunkTexels source texels, within one face), each chunk's sum
// added to the accumulator, with a barrier between chunks; the last chunk writes the output mip.
#include <algorithm>
#include <cstdint>

#include <reference_b10g11r11.spv.h>
#include <reference_rgba16f.spv.h>
#include <reference_rgba32f.spv.h>

#include "filter_impl.h"

namespace probe::gpu {

namespace {

// Source texels per chunk: bounds each invocation's loop iterations (lavapipe stops an invocation's
// loops after 65535 in all) and each dispatch's time (GPUs reset a device whose dispatch runs long).
constexpr int kChunkTexels = 16384;

struct ReferenceConstants {
    int32_t sourceSize;
    int32_t outLevel;
    float alpha2;   // GGX
    float exponent; // Charlie (shaders/lobe.glsl)
    int32_t lobe;   // 0: GGX, 1: Charlie
    int32_t firstRow;
    int32_t rowCount;
    int32_t stage;
};

} // namespace

std::unique_ptr<ComputePipeline> makeReferencePipeline(const Filter::Impl& impl) {
    return impl.pipeline(outputVariant(impl, {kReferenceRgba32fSpv, kReferenceRgba16fSpv, kReferenceB10g11r11Spv}));
}

namespace {

int rowsPerChunk(const FilterSettings& s) { return std::clamp(kChunkTexels / s.faceSize, 1, s.faceSize); }

} // namespace

uint32_t referenceDispatchCount(const Filter::Impl& impl) {
    const int rows = kFaceCount * impl.settings.faceSize, chunk = rowsPerChunk(impl.settings);
    return uint32_t((rows + chunk - 1) / chunk);
}

void recordReferenceLevel(Filter::Impl& impl, VkCommandBuffer commandBuffer, int m) {
    const FilterSettings& s = impl.settings;
    const double alpha = lobeAlpha(s.method.lobe, levelAlpha(s.mapping, m, s.levelCount));
    const LobeConstants lobe = lobeConstants(s.method.lobe, alpha);
    const int chunk = rowsPerChunk(s);
    const int rows = kFaceCount * s.faceSize;
    for (int firstRow = 0; firstRow < rows; firstRow += chunk) {
        if (firstRow > 0) impl.barrier(commandBuffer);
        const int stage = (firstRow == 0 ? 1 : 0) | (firstRow + chunk >= rows ? 2 : 0);
        const ReferenceConstants constants{s.faceSize,
                                           m,
                                           static_cast<float>(lobe.alpha2),
                                           static_cast<float>(lobe.exponent),
                                           s.method.lobe == Lobe::charlie ? 1 : 0,
                                           firstRow,
                                           chunk,
                                           stage};
        dispatchPass(impl, commandBuffer, *impl.pass2, "reference", m, constants, groupsFor(texelCount(s.faceSize >> m)));
    }
}

} // namespace probe::gpu
