// The conversion pass for a B10G11R11 output on a device that cannot store that format: one mip of
// the RGBA32F output that pass 2 wrote, packed into 32-bit words (R in bits 0-10, G in 11-21, B in
// 22-31: unsigned floats with 5-bit exponents and 6-, 6- and 5-bit mantissas, rounded to nearest,
// at most the largest finite value) of an R32_UINT image that the host then copies into the
// caller's B10G11R11 image (the two formats are size-compatible).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
#include "probe/shared_constants.h"

layout(local_size_x = PROBE_WORKGROUP_SIZE) in;

// The RGBA32F mip, and the words written at element 0 of images.glsl's written mips.
layout(set = 0, binding = 6) uniform sampler2DArray convertInput;
layout(set = 0, binding = 7, r32ui) uniform writeonly uimage2DArray convertOutput;

layout(push_constant) uniform Params {
    int size; // face size of the mip
} params;

// A non-negative float as an unsigned float of `mantissaBits` (6 or 5) with half's 5-bit exponent:
// half's bits rounded to nearest at the shorter mantissa, capped at the largest finite value.
uint packUnsignedFloat(float value, uint mantissaBits) {
    uint bits = packHalf2x16(vec2(min(max(value, 0.0), PROBE_HALF_MAX), 0.0)) & 0x7fffu;
    uint drop = 10u - mantissaBits;
    uint largest = (30u << mantissaBits) | ((1u << mantissaBits) - 1u);
    return min((bits + (1u << (drop - 1u))) >> drop, largest);
}

void main() {
    uint index = invocationIndex();
    uint s = uint(params.size);
    if (index >= 6u * uint(kBatchSize) * s * s) return; // every layer of a batch's cubes
    ivec3 t = ivec3(int(index % s), int((index / s) % s), int(index / (s * s)));
    vec3 c = texelFetch(convertInput, t, 0).rgb;
    uint packed = packUnsignedFloat(c.r, 6u) | (packUnsignedFloat(c.g, 6u) << 11) | (packUnsignedFloat(c.b, 5u) << 22);
    imageStore(convertOutput, t, uvec4(packed));
}
