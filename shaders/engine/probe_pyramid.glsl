// Pass 1 of probefilter's table method as a drop-in compute shader for an engine's own pipeline: one
// mip of the pyramid that engine/probe_table_filter.glsl reads, made from the mip above it by the
// B-spline pass a table was fitted for (docs/design.md), each of its four taps one bilinear
// textureLod through a seamless sampler. It needs no library and no buffers.
//
//   #version 450
//   #extension GL_GOOGLE_include_directive : require
//   #define PROBE_PYRAMID_FORMAT rgba16f      // optional: the pyramid image's format (default rgba16f)
//   #define PROBE_TABLE_PYRAMID_ONLY          // the table's pyramid pass without its coefficients
//   #include "gltf128_quad8.glsl"             // the table the pyramid is for
//   #include "engine/probe_pyramid.glsl"      // this file
//
// Set 0 (PROBE_SET to change it):
//   binding 0 (PROBE_FINE_BINDING)    samplerCube: mip k - 1 of the pyramid alone (a cube view of that
//     one mip). Sampler: linear min/mag filter, clamp to edge; the table filter's sampler serves.
//     Layout SHADER_READ_ONLY_OPTIMAL (or GENERAL).
//   binding 1 (PROBE_COARSE_BINDING)  image2DArray, writeonly: mip k, its six faces as layers, layout
//     GENERAL.
// Push constant: none. Mip 0 is the source, written by the engine, its values clamped where it is
// written to the pyramid format's range (+-65504 for rgba16f: a larger float becomes Inf there and
// spreads through every mip; +-2^64 for rgba32f, which keeps the filter's sums finite).
// Dispatch: (ceil(S / 8), ceil(S / 8), 6) workgroups, S the face size of mip k, for k = 1 .. log2(S_0)
// in order, with a barrier between (mip k reads mip k - 1). Outputs are clamped to +-PROBE_PYRAMID_MAX,
// the format's largest finite value (default 65504, the largest half: define it for a wider format).
#ifndef PROBE_ENGINE_PYRAMID_GLSL
#define PROBE_ENGINE_PYRAMID_GLSL

#ifndef PROBE_TABLE_PYRAMID_BSPLINE
#error "include a generated table (tables/<name>.glsl) before engine/probe_pyramid.glsl"
#endif
#if PROBE_TABLE_PYRAMID_BSPLINE == 0
#error "the table was fitted for the box pyramid; engine/probe_pyramid.glsl builds the B-spline one"
#endif
#ifndef PROBE_SET
#define PROBE_SET 0
#endif
#ifndef PROBE_FINE_BINDING
#define PROBE_FINE_BINDING 0
#endif
#ifndef PROBE_COARSE_BINDING
#define PROBE_COARSE_BINDING 1
#endif
#ifndef PROBE_PYRAMID_FORMAT
#define PROBE_PYRAMID_FORMAT rgba16f
#endif
// The largest finite half; define PROBE_PYRAMID_MAX for a wider format.
#ifndef PROBE_PYRAMID_MAX
#define PROBE_PYRAMID_MAX vec3(PROBE_HALF_MAX)
#endif

#include "cube.glsl"
#include "probe/shared_constants.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(set = PROBE_SET, binding = PROBE_FINE_BINDING) uniform samplerCube probeFine;
layout(set = PROBE_SET, binding = PROBE_COARSE_BINDING, PROBE_PYRAMID_FORMAT) uniform writeonly image2DArray probeCoarse;

vec3 probeSampleFine(int face, float x, float y, int fineSize) {
    vec2 uv = texelToFaceUv(x, y, fineSize);
    return textureLod(probeFine, faceUvToCubePoint(face, uv.x, uv.y), 0.0).rgb;
}
#include "pyramid_bspline.glsl"

void main() {
    int size = imageSize(probeCoarse).x;
    ivec3 t = ivec3(gl_GlobalInvocationID);
    if (t.x >= size || t.y >= size) return;
    vec3 value = pyramidBspline(t.z, t.x, t.y, 2 * size, PROBE_TABLE_PYRAMID_INVERSE_SOLID_ANGLE != 0);
    imageStore(probeCoarse, t, vec4(clamp(value, -PROBE_PYRAMID_MAX, PROBE_PYRAMID_MAX), 1.0));
}

#endif
