// The image bindings of probe::gpu::Filter, beside buffers.glsl's buffers (filter_resources.h):
// the source cube, the pyramid as a cube image with mips (hardware sampling), and the output cube's
// mips. A shader compiled for one output (or pyramid) format defines PROBE_OUTPUT_FORMAT (or
// PROBE_PYRAMID_FORMAT) as its GLSL image format and PROBE_OUTPUT_MAX (PROBE_PYRAMID_MAX) as that
// format's largest finite value per channel (shaders/CMakeLists.txt makes one SPIR-V per format).
#ifndef PROBE_IMAGES_GLSL
#define PROBE_IMAGES_GLSL

#include "probe/shared_constants.h"

#ifndef PROBE_OUTPUT_FORMAT
#define PROBE_OUTPUT_FORMAT rgba32f
#define PROBE_OUTPUT_MAX vec3(3.40282347e38)
#endif
#ifndef PROBE_PYRAMID_FORMAT
#define PROBE_PYRAMID_FORMAT rgba32f
#define PROBE_PYRAMID_MAX vec3(3.40282347e38)
#endif

// The source at S_0, read through a nearest sampler at texel centres: exact texels.
layout(set = 0, binding = 5) uniform samplerCube sourceCube;
// The pyramid through a seamless trilinear sampler: pass 2 reads every level; pass 1 reads the level
// above the one it writes (a view of that mip alone).
layout(set = 0, binding = 6) uniform samplerCube pyramidCube;
// Pass 1 (hardware sampling): the pyramid mip written, faces as layers.
layout(set = 0, binding = 7, PROBE_PYRAMID_FORMAT) uniform writeonly image2DArray pyramidMip;
// Pass 1 (hardware sampling), its last dispatch (pyramid_tail.comp): the mips of face size
// PROBE_PYRAMID_TAIL_SIZE (8) and below that it writes, the largest first, faces as layers.
layout(set = 0, binding = 10, PROBE_PYRAMID_FORMAT) uniform writeonly image2DArray pyramidTailMips[4];
// Pass 2: the output cube's mip of the dispatch's level, faces as layers.
layout(set = 0, binding = 8, PROBE_OUTPUT_FORMAT) uniform writeonly image2DArray outputMip;

// The source texel of a direction (the texel whose footprint holds it), clamped to
// +-PROBE_FILTER_RANGE_LIMIT: every pass reads the source through here (pass 1's level 0, the copied
// levels), so the sums after it stay finite whatever finite values the caller's cube holds.
vec3 sourceTexel(vec3 direction) {
    return clamp(textureLod(sourceCube, direction, 0.0).rgb, -PROBE_FILTER_RANGE_LIMIT, PROBE_FILTER_RANGE_LIMIT);
}

// Texel `index` of a level of face size `size` (face-major, row-major: probe::texelIndex) as image
// coordinates (i, j, face).
ivec3 texelCoordinates(uint index, int size) {
    uint s = uint(size), r = index % (s * s);
    return ivec3(int(r % s), int(r / s), int(index / (s * s)));
}

// Writes an output texel, clamped to the format's largest finite magnitude so that no texel is Inf.
void storeOutput(ivec3 texel, vec3 value) { imageStore(outputMip, texel, vec4(clamp(value, -PROBE_OUTPUT_MAX, PROBE_OUTPUT_MAX), 1.0)); }

#endif
