// Order-2 SH projection of a cube (core's probe::projectRadiance): L_lm = sum_t L(t) Y_lm(l_t)
// dOmega_t, summed in a fixed order so that every run gives the same bits. Each workgroup sums
// 1024 items: every invocation 16 consecutive ones in order, then a tree over the 64 invocations.
// The first dispatch's items are the source texels (pyramid level 0, directions and solid angles
// from the geometry buffer); each further dispatch sums blocks of the one before, until one block
// is left. A block is 9 vec4 (rgb of each coefficient) in the output buffer.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
#include "sh.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE) in;

#define ITEMS_PER_INVOCATION 16u
#define ITEMS_PER_GROUP (64u * ITEMS_PER_INVOCATION)

layout(push_constant) uniform Params {
    uint count;      // items to sum
    uint inFirst;    // blocks: the first input block (in vec4s)
    uint outFirst;   // the first output block (in vec4s); workgroup g writes block g
    uint fromSource; // 1: the items are source texels; 0: blocks
} params;

shared vec3 partial[64][PROBE_SH_COUNT];

void main() {
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (group * ITEMS_PER_GROUP >= params.count) return; // a whole workgroup past the end
    uint local = gl_LocalInvocationID.x;

    vec3 sum[PROBE_SH_COUNT];
    for (int c = 0; c < PROBE_SH_COUNT; ++c) sum[c] = vec3(0.0);
    uint first = group * ITEMS_PER_GROUP + local * ITEMS_PER_INVOCATION;
    for (uint k = 0u; k < ITEMS_PER_INVOCATION; ++k) {
        uint item = first + k;
        if (item >= params.count) break;
        if (params.fromSource != 0u) {
            vec4 g = geometryTexel(item);
            vec3 radiance = pyramidTexel(item) * g.w;
            float y[PROBE_SH_COUNT];
            shBasis(g.xyz, y);
            for (int c = 0; c < PROBE_SH_COUNT; ++c) sum[c] += radiance * y[c];
        } else {
            for (int c = 0; c < PROBE_SH_COUNT; ++c) sum[c] += outputTexels[params.inFirst + item * uint(PROBE_SH_COUNT) + uint(c)].rgb;
        }
    }
    for (int c = 0; c < PROBE_SH_COUNT; ++c) partial[local][c] = sum[c];
    barrier();
    for (uint stride = 32u; stride > 0u; stride >>= 1u) {
        if (local < stride)
            for (int c = 0; c < PROBE_SH_COUNT; ++c) partial[local][c] += partial[local + stride][c];
        barrier();
    }
    if (local == 0u)
        for (int c = 0; c < PROBE_SH_COUNT; ++c)
            outputTexels[params.outFirst + group * uint(PROBE_SH_COUNT) + uint(c)] = vec4(partial[0][c], 0.0);
}
