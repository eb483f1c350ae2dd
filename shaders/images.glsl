// The image bindings of probe::gpu::Filter, beside buffers.glsl's buffers (filter_descriptors.h):
// the source cube, the pyramid as a cube image with mips (hardware sampling), and the mips a dispatch
// writes. A shader that writes pyramid mips is compiled with PROBE_PYRAMID_FORMAT as their GLSL image
// format and PROBE_PYRAMID_MAX as its largest finite value per channel; any other shader writes
// output mips, of PROBE_OUTPUT_FORMAT and PROBE_OUTPUT_MAX (shaders/CMakeLists.txt makes one SPIR-V
// per format).
#ifndef PROBE_IMAGES_GLSL
#define PROBE_IMAGES_GLSL

#include "batch.glsl"
#include "probe/shared_constants.h"

#if !defined(PROBE_PYRAMID_FORMAT) && !defined(PROBE_OUTPUT_FORMAT)
#define PROBE_OUTPUT_FORMAT rgba32f
#define PROBE_OUTPUT_MAX vec3(3.40282347e38)
#endif

// The source at S_0, read through a nearest sampler at texel centres: exact texels.
// The pyramid through a seamless trilinear sampler: pass 2 reads every level; pass 1 reads the level
// above the one it writes (a view of that mip alone).
// With PROBE_BATCH both are cube-map arrays, read at the invocation's cube (batch.glsl).
#ifdef PROBE_BATCH
layout(set = 0, binding = 5) uniform samplerCubeArray sourceCube;
layout(set = 0, binding = 6) uniform samplerCubeArray pyramidCube;
vec4 sourceRead(vec3 direction) { return textureLod(sourceCube, vec4(direction, float(batchCube)), 0.0); }
vec3 pyramidRead(vec3 direction, float level) { return textureLod(pyramidCube, vec4(direction, float(batchCube)), level).rgb; }
#else
layout(set = 0, binding = 5) uniform samplerCube sourceCube;
layout(set = 0, binding = 6) uniform samplerCube pyramidCube;
vec4 sourceRead(vec3 direction) { return textureLod(sourceCube, direction, 0.0); }
vec3 pyramidRead(vec3 direction, float level) { return textureLod(pyramidCube, direction, level).rgb; }
#endif
// The mips a dispatch writes, faces as layers (batchLayer), from element 0: pass 1's pyramid mip
// (hardware sampling), or in its last dispatch (pyramid_tail.comp) the mips of face size
// PROBE_PYRAMID_TAIL_SIZE (8) down to 1, the largest first; or pass 2's output mip, or with
// PROBE_LEVEL_GROUP the output mips of its level group (level_group.glsl): PROBE_LEVEL_GROUP_WIDTH of
// them, 4 or, in the variant for devices that offer as many storage images per stage,
// PROBE_MAX_GROUP_LEVELS. One binding for all keeps every other pipeline within the four storage
// images per stage that every Vulkan device offers.
#ifndef PROBE_LEVEL_GROUP_WIDTH
#define PROBE_LEVEL_GROUP_WIDTH 4
#endif
#if PROBE_LEVEL_GROUP_WIDTH != 4 && PROBE_LEVEL_GROUP_WIDTH != PROBE_MAX_GROUP_LEVELS
#error "storeOutput writes groups of 4 or of PROBE_MAX_GROUP_LEVELS levels"
#endif
#if defined(PROBE_PYRAMID_SHARED_EXPONENT)
// An E5B9G9R9 pyramid, which no device stores to: its mips are written as bits through R32_UINT views.
layout(set = 0, binding = 7, PROBE_PYRAMID_FORMAT) uniform writeonly uimage2DArray pyramidMips[4];
#elif defined(PROBE_PYRAMID_FORMAT)
layout(set = 0, binding = 7, PROBE_PYRAMID_FORMAT) uniform writeonly image2DArray pyramidMips[4];
#elif defined(PROBE_LEVEL_GROUP)
layout(set = 0, binding = 7, PROBE_OUTPUT_FORMAT) uniform writeonly image2DArray outputMips[PROBE_LEVEL_GROUP_WIDTH];
#else
layout(set = 0, binding = 7, PROBE_OUTPUT_FORMAT) uniform writeonly image2DArray outputMip;
#endif

// The source texel of a direction (the texel whose footprint holds it), clamped to
// +-PROBE_FILTER_RANGE_LIMIT: every pass reads the source through here (pass 1's level 0, the copied
// levels), so the sums after it stay finite whatever finite values the caller's cube holds.
vec3 sourceTexel(vec3 direction) {
    return clamp(sourceRead(direction).rgb, -PROBE_FILTER_RANGE_LIMIT, PROBE_FILTER_RANGE_LIMIT);
}

// Texel `index` of a level of face size `size` (face-major, row-major: probe::texelIndex) as image
// coordinates (i, j, face).
ivec3 texelCoordinates(uint index, int size) {
    uint s = uint(size), r = index % (s * s);
    return ivec3(int(r % s), int(r / s), int(index / (s * s)));
}

#if defined(PROBE_PYRAMID_FORMAT)
// A value clamped to the pyramid format's range: its largest finite value, and 0 for the unsigned
// E5B9G9R9.
vec3 pyramidRange(vec3 value) {
#if defined(PROBE_PYRAMID_SHARED_EXPONENT)
    return clamp(value, 0.0, PROBE_PYRAMID_MAX.x);
#else
    return clamp(value, -PROBE_PYRAMID_MAX, PROBE_PYRAMID_MAX);
#endif
}

#if defined(PROBE_PYRAMID_SHARED_EXPONENT)
// E5B9G9R9 bits of `c` (in range), rounded to nearest: the conversion of the Vulkan specification
// ("Shared Exponent Formats"), with the exponent taken exactly by frexp.
uint packRgb9e5(vec3 c) {
    float largest = max(c.r, max(c.g, c.b));
    int e;
    frexp(largest, e);                 // largest = f 2^e, f in [0.5, 1): floor(log2(largest)) = e - 1
    int exponent = max(e - 1, -16) + 16; // biased by 15, plus 1: the mantissas have no implicit leading one
    if (floor(ldexp(largest, 24 - exponent) + 0.5) == 512.0) exponent += 1; // rounded up into the next exponent
    uvec3 m = uvec3(floor(ldexp(c, ivec3(24 - exponent)) + 0.5));
    return m.r | (m.g << 9) | (m.b << 18) | (uint(exponent) << 27);
}
#endif

// Writes texel (i, j, face) of the invocation's cube in pyramid mip `element` of the dispatch, clamped
// to the format's range. Constant indices: a dynamic one needs a device feature.
void storePyramidMip(int element, ivec3 texel, vec3 value) {
    texel = batchLayer(texel);
#if defined(PROBE_PYRAMID_SHARED_EXPONENT)
    uvec4 v = uvec4(packRgb9e5(pyramidRange(value)));
#else
    vec4 v = vec4(pyramidRange(value), 1.0);
#endif
    switch (element) {
    case 0: imageStore(pyramidMips[0], texel, v); break;
    case 1: imageStore(pyramidMips[1], texel, v); break;
    case 2: imageStore(pyramidMips[2], texel, v); break;
    default: imageStore(pyramidMips[3], texel, v); break;
    }
}
#endif

#if defined(PROBE_LEVEL_GROUP)
// Writes an output texel (i, j, face) of the invocation's cube in the group's level `slot`, clamped to
// the format's largest finite magnitude so that no texel is Inf. Constant indices: a dynamic one
// needs a device feature.
void storeOutput(uint slot, ivec3 texel, vec3 value) {
    texel = batchLayer(texel);
    vec4 v = vec4(clamp(value, -PROBE_OUTPUT_MAX, PROBE_OUTPUT_MAX), 1.0);
    switch (slot) {
    case 0u: imageStore(outputMips[0], texel, v); break;
    case 1u: imageStore(outputMips[1], texel, v); break;
    case 2u: imageStore(outputMips[2], texel, v); break;
#if PROBE_LEVEL_GROUP_WIDTH == 4
    default: imageStore(outputMips[3], texel, v); break;
#else
    case 3u: imageStore(outputMips[3], texel, v); break;
    case 4u: imageStore(outputMips[4], texel, v); break;
    case 5u: imageStore(outputMips[5], texel, v); break;
    case 6u: imageStore(outputMips[6], texel, v); break;
    case 7u: imageStore(outputMips[7], texel, v); break;
    case 8u: imageStore(outputMips[8], texel, v); break;
    case 9u: imageStore(outputMips[9], texel, v); break;
    case 10u: imageStore(outputMips[10], texel, v); break;
    default: imageStore(outputMips[11], texel, v); break;
#endif
    }
}
#elif !defined(PROBE_PYRAMID_FORMAT)
// Writes an output texel (i, j, face) of the invocation's cube, clamped to the format's largest finite
// magnitude so that no texel is Inf.
void storeOutput(ivec3 texel, vec3 value) {
    imageStore(outputMip, batchLayer(texel), vec4(clamp(value, -PROBE_OUTPUT_MAX, PROBE_OUTPUT_MAX), 1.0));
}
#endif

#endif
