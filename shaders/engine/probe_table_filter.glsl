// Pass 2 of probefilter's table method as a drop-in compute shader for an engine's own pipeline:
// one output level of a GGX-filtered cube map from a tap table (Manson & Sloan), each tap one
// trilinear textureLod of the pyramid through a seamless sampler. It needs no library and no
// buffers: the table is a generated include (tables/<name>.glsl) compiled into the shader.
//
//   #version 450
//   #extension GL_GOOGLE_include_directive : require
//   #define PROBE_OUTPUT_FORMAT rgba16f       // optional: the output image's format (default rgba16f)
//   #define PROBE_OUTPUT_MAX vec3(65504.0)    // optional: its largest finite value (below)
//   #include "gltf128_quad8.glsl"             // the table (include path: the tables folder)
//   #include "engine/probe_table_filter.glsl" // this file (include path: the shaders folder)
//
// Set 0 (PROBE_SET to change it):
//   binding 0 (PROBE_PYRAMID_BINDING)  samplerCube: the pyramid, a cube with the full mip chain of
//     face size PROBE_TABLE_FACE_SIZE, mip k made from mip k - 1 by the pyramid pass the table was
//     fitted for (engine/probe_pyramid.glsl: the B-spline pass of docs/design.md). Sampler: linear
//     min/mag filter, linear mipmap mode, clamp to edge, no LOD bias, maxLod at least the last mip;
//     seamless cube filtering, which Vulkan always does.
//     Layout SHADER_READ_ONLY_OPTIMAL. Its values must lie within the pyramid format's range
//     (engine/probe_pyramid.glsl: clamp where mip 0 is written) and +-2^64: then every tap's
//     weighted sum stays finite, for any finite source.
//   binding 1 (PROBE_OUTPUT_BINDING)   image2DArray, writeonly: the output level's mip, its six faces
//     as layers (a 2D-array view of one mip of the output cube), layout GENERAL.
// Push constant: int level, an output level that the table filters, one with taps
// (probeTableTapGroups[level] > 0, kTapGroups in the C++ header tables/<name>.h). With the
// glTF, Filament and Unity mappings that is 1 .. PROBE_TABLE_LEVEL_COUNT - 1: their level 0 has
// alpha 0 and is a copy of the source (copy mip 0 instead of dispatching). The authors' mapping
// filters level 0 too: dispatch 0 .. PROBE_TABLE_LEVEL_COUNT - 1.
// Dispatch: (ceil(S / 8), ceil(S / 8), 6) workgroups, S = PROBE_TABLE_FACE_SIZE >> level; z is the
// face, +X, -X, +Y, -Y, +Z, -Z (a workgroup's face gives the table entries all its invocations read).
// Dispatch every level with no barrier or timestamp between them (they write different mips and read
// only the pyramid): a GPU then overlaps the small levels, which alone leave it mostly idle.
// Outputs are clamped to >= 0 and to PROBE_OUTPUT_MAX, by default 65504, the largest finite half:
// define it for another format (vec3(3.40282347e38) for rgba32f; for r11f_g11f_b10f
// vec3(PROBE_FLOAT11_MAX, PROBE_FLOAT11_MAX, PROBE_FLOAT10_MAX) from probe/shared_constants.h).
#ifndef PROBE_ENGINE_TABLE_FILTER_GLSL
#define PROBE_ENGINE_TABLE_FILTER_GLSL

#extension GL_EXT_control_flow_attributes : require

#ifndef PROBE_TABLE_FACE_SIZE
#error "include a generated table (tables/<name>.glsl) before engine/probe_table_filter.glsl"
#endif
#ifdef PROBE_TABLE_PYRAMID_ONLY
#error "the table was included without its coefficients (PROBE_TABLE_PYRAMID_ONLY is for engine/probe_pyramid.glsl)"
#endif
#ifndef PROBE_SET
#define PROBE_SET 0
#endif
#ifndef PROBE_PYRAMID_BINDING
#define PROBE_PYRAMID_BINDING 0
#endif
#ifndef PROBE_OUTPUT_BINDING
#define PROBE_OUTPUT_BINDING 1
#endif
#ifndef PROBE_OUTPUT_FORMAT
#define PROBE_OUTPUT_FORMAT rgba16f
#endif

#include "cube.glsl"
#include "probe/shared_constants.h"
#include "tap_sum.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(set = PROBE_SET, binding = PROBE_PYRAMID_BINDING) uniform samplerCube probePyramid;
layout(set = PROBE_SET, binding = PROBE_OUTPUT_BINDING, PROBE_OUTPUT_FORMAT) uniform writeonly image2DArray probeOutput;

layout(push_constant) uniform ProbeTableParams {
    int level;
} probeParams;

#define PROBE_TAPS PROBE_TABLE_TAPS
#define PROBE_COEFFICIENTS PROBE_TABLE_COEFFICIENT_COUNT
vec4 probeTableEntry(uint index) {
    return probeTableCoeffs[uint(probeParams.level) * uint(5 * PROBE_COEFFICIENTS * 3 * PROBE_TAPS / 4) + index];
}
vec3 probeSamplePyramid(vec3 direction, float level) { return textureLod(probePyramid, direction, level).rgb; }
#include "table_taps.glsl"

void main() {
    int size = PROBE_TABLE_FACE_SIZE >> probeParams.level;
    ivec3 t = ivec3(gl_GlobalInvocationID);
    if (t.x >= size || t.y >= size) return;
    vec3 d = texelCubePoint(t.z, t.x, t.y, size);
    int groupsInUse = max(probeTableTapGroups[probeParams.level], 1);
    // The face's axis (faces +X, -X, +Y, -Y, +Z, -Z), from the workgroup: the same across it, so
    // that a GPU reads the table entries its frames need once for all its invocations.
    int major = int(gl_WorkGroupID.z) / 2;
    vec3 sum = vec3(0.0);
    float weightSum = 0.0;
    addTableFrame(d, (major + 1) % 3, groupsInUse, false, sum, weightSum);
    addTableFrame(d, (major + 2) % 3, groupsInUse, false, sum, weightSum);
    if (frameWeight(d, major) > 0.0) addTableFrame(d, major, groupsInUse, false, sum, weightSum);
    // The largest finite half, so that an rgba16f output holds no Inf; define PROBE_OUTPUT_MAX for a
    // wider format.
#ifndef PROBE_OUTPUT_MAX
#define PROBE_OUTPUT_MAX vec3(PROBE_HALF_MAX)
#endif
    imageStore(probeOutput, t, vec4(min(finishTapSum(sum, weightSum), PROBE_OUTPUT_MAX), 1.0));
}

#endif
