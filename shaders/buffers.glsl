// The buffers every pass binds (probe/runtime.h's layout, compute_pipeline.h's one descriptor set):
// all levels of one cube are packed level after level, each level face-major and row-major
// (probe::texelIndex), one RGBA32F texel per vec4. The buffers that the hot loops only read are read
// as uniform texel buffers (tableEntry, pyramidTexel), which a CPU device's SIMD back end gathers
// without branches; the hardware-sampling pipelines read the table as a storage buffer instead.
#ifndef PROBE_BUFFERS_GLSL
#define PROBE_BUFFERS_GLSL

#include "batch.glsl"
#include "probe/shared_constants.h"

// Pass 1's pyramid of the source: level 0 is the source at S_0, down to 1x1. Each face of each level
// carries a one-texel border (pyramid.comp fills it from the adjacent faces), so that a bilinear
// read never leaves its face: a level of face size S holds texels (i, j), i and j in [-1, S].
// Written here through a window of the buffer that starts at one of its texels (the whole buffer
// can exceed the storage-buffer range a device guarantees: storePyramid), read through
// pyramidTexel.
// pyramid.comp (PROBE_PYRAMID_READBACK) reads back what its dispatch's other workgroups wrote.
#ifdef PROBE_PYRAMID_READBACK
layout(std430, set = 0, binding = 0) coherent buffer PyramidBuffer { vec4 pyramid[]; };
#else
layout(std430, set = 0, binding = 0) writeonly buffer PyramidBuffer { vec4 pyramid[]; };
#endif
// Results in a buffer: the reference's running sums per output texel (level m of face size
// S_0 >> m), the SH projection's partial sums, the sphere renderer's pixels.
layout(std430, set = 0, binding = 1) buffer OutputBuffer { vec4 outputTexels[]; };
// Per level of the pyramid, the texel centre directions (xyz, unit) and exact solid angles (w),
// computed by probecore's CubeGeometry in double, for exact sampling and the box pyramid (hardware
// sampling computes its directions, and the Filter then binds a single texel here). A texel buffer,
// read through geometryTexel: it is as large as the pyramid.
layout(set = 0, binding = 2) uniform samplerBuffer geometryTexels;
// Pass 2's tap table, or the FIS samples (the sphere renderer's parameters).
layout(set = 0, binding = 3) uniform samplerBuffer tableTexels;
// The pyramid buffer of binding 0, for reads.
layout(set = 0, binding = 4) uniform samplerBuffer pyramidTexels;
// The buffer of binding 3 again, for the pipelines that sample the pyramid image (the GPU path):
// their table reads have indices that the whole workgroup shares, which a GPU serves once per
// wave from its scalar or constant path, where a texel fetch costs a texture-unit read per
// invocation (docs/benchmarks.md, "Static GPU cost").
layout(std430, set = 0, binding = 8) restrict readonly buffer TableBuffer { vec4 tableData[]; };

#ifdef PROBE_HARDWARE_SAMPLING
vec4 tableEntry(uint index) { return tableData[index]; }
#else
vec4 tableEntry(uint index) { return texelFetch(tableTexels, int(index)); }
#endif
vec3 pyramidTexel(uint index) { return texelFetch(pyramidTexels, int(index)).rgb; }
vec4 geometryTexel(uint index) { return texelFetch(geometryTexels, int(index)); }

// Writes pyramid texel `index` through the window bound at binding 0, which starts at texel `window`.
void storePyramid(uint index, uint window, vec3 value) { pyramid[index - window] = vec4(value, 1.0); }

// Index of the first texel of `level` in a packed cube whose level 0 has face size `faceSize` (a
// power of two): 6 sum_{k < level} (S >> k)^2 = 8 (S^2 - (S >> level)^2).
uint levelOffset(int faceSize, int level) {
    uint s0 = uint(faceSize), s = uint(faceSize >> level);
    return 8u * (s0 * s0 - s * s);
}

// Index of the first texel of pyramid `level`, each face (S + 2)^2 with its border:
// 6 sum_{k < level} (S_k + 2)^2 = 8 (S_0^2 - S^2) + 48 (S_0 - S) + 24 level.
uint pyramidLevelOffset(int faceSize, int level) {
    uint s0 = uint(faceSize), s = uint(faceSize >> level);
    return 8u * (s0 * s0 - s * s) + 48u * (s0 - s) + 24u * uint(level);
}

// Index of the first texel of the invocation's cube in `level` of a batch's pyramid buffer, which
// holds each level of every cube in turn (so that a level's faces and cubes are one run of layers).
uint pyramidLevelFirst(int faceSize, int level) {
    uint row = uint((faceSize >> level) + 2);
    return uint(kBatchSize) * pyramidLevelOffset(faceSize, level) + uint(6 * batchCube) * row * row;
}

// Index of texel (i, j) of `face`, i and j in [-1, size], within a bordered pyramid level of `size`
// (probe::gpu::pyramidTexelIndex).
uint pyramidTexelIndex(int face, int i, int j, int size) {
    uint row = uint(size + 2);
    return (uint(face) * row + uint(j + 1)) * row + uint(i + 1);
}

// The linear invocation index of a dispatch of (x, y) workgroups: dispatches with more than 65535
// workgroups are split over y (probe runtime's ComputePipeline::dispatch).
uint invocationIndex() {
    return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * uint(PROBE_WORKGROUP_SIZE) + gl_GlobalInvocationID.x;
}

#endif
