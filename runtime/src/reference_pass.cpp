// The exact reference on the GPU (shaders/reference.comp): per output level computed, one dispatch
// per chunk of source rows (at most kChunkTexels source texels, within one face), each chunk's sum
// added to the accumulator, with a barrier between chunks; the last chunk writes the output mip.
#include <algorithm>
#include <cstdint>

#include <reference_b10g11r11.spv.h>
#include <reference_rgba16f.spv.h>
#include <reference_rgba32f.spv.h>

#include "filter_passes.h"

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

ReferencePass::ReferencePass(const PassContext& context) : context_(context) {
    pipeline_ = context.pipeline(context.outputVariant({kReferenceRgba32fSpv, kReferenceRgba16fSpv, kReferenceB10g11r11Spv}));
}

namespace {

int rowsPerChunk(const FilterSettings& s) { return std::clamp(kChunkTexels / s.faceSize, 1, s.faceSize); }

} // namespace

uint32_t ReferencePass::dispatchCount() const {
    const int rows = kFaceCount * context_.settings.faceSize, chunk = rowsPerChunk(context_.settings);
    return uint32_t((rows + chunk - 1) / chunk);
}

void ReferencePass::record(const PassRecorder& recorder, int m) const {
    const FilterSettings& s = context_.settings;
    const double alpha = lobeAlpha(s.method.lobe, levelAlpha(s.mapping, m, s.levelCount));
    const LobeConstants lobe = lobeConstants(s.method.lobe, alpha);
    const int chunk = rowsPerChunk(s);
    const int rows = kFaceCount * s.faceSize;
    for (int firstRow = 0; firstRow < rows; firstRow += chunk) {
        if (firstRow > 0) recorder.barrier();
        const int stage = (firstRow == 0 ? 1 : 0) | (firstRow + chunk >= rows ? 2 : 0);
        const ReferenceConstants constants{s.faceSize,
                                           m,
                                           static_cast<float>(lobe.alpha2),
                                           static_cast<float>(lobe.exponent),
                                           s.method.lobe == Lobe::charlie ? 1 : 0,
                                           firstRow,
                                           chunk,
                                           stage};
        recorder.dispatch(*pipeline_, "reference", m, constants, groupsFor(texelCount(s.faceSize >> m)));
    }
}

} // namespace probe::gpu
