// The storage buffers every pass binds (probe/runtime.h's layout, one descriptor set):
// all levels of one cube are packed level after level, each level face-major and row-major
// (probe::texelIndex), one RGBA32F texel per vec4.
#ifndef PROBE_BUFFERS_GLSL
#define PROBE_BUFFERS_GLSL

// Pass 1's pyramid of the source: level 0 is the source at S_0, down to 1x1.
layout(std430, set = 0, binding = 0) buffer PyramidBuffer { vec4 pyramid[]; };
// The filtered output: level m has face size S_0 >> m.
layout(std430, set = 0, binding = 1) buffer OutputBuffer { vec4 outputTexels[]; };
// Per level of the pyramid, the texel centre directions (xyz, unit) and exact solid angles (w),
// computed by probecore's CubeGeometry in double.
layout(std430, set = 0, binding = 2) readonly buffer GeometryBuffer { vec4 geometry[]; };
// Pass 2's tap table, or the FIS sample directions.
layout(std430, set = 0, binding = 3) readonly buffer TableBuffer { vec4 table[]; };

// Index of the first texel of `level` in a packed cube whose level 0 has face size `baseSize` (a
// power of two): 6 sum_{k < level} (S >> k)^2 = 8 (S^2 - (S >> level)^2).
uint levelOffset(int baseSize, int level) {
    uint s0 = uint(baseSize), s = uint(baseSize >> level);
    return 8u * (s0 * s0 - s * s);
}

// The linear invocation index of a dispatch of (x, y) workgroups: dispatches with more than 65535
// workgroups are split over y (probe runtime's ComputePipeline::dispatch).
uint invocationIndex() {
    return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
}

#endif
