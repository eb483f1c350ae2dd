// Pass 1, its small mips in one dispatch: one workgroup (per cube of a batch) builds mips params.level
// (face size PROBE_PYRAMID_TAIL_SIZE or less) to params.lastLevel (pyramid_tail.glsl). The first mip
// reads the one above through the sampler, as pyramid_image.comp does (with PROBE_EXACT_TAIL, exact
// sampling's: from the bordered buffer, as pyramid.comp does).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
#include "cube.glsl"
#include "images.glsl"
#include "probe/shared_constants.h"
#include "footprint.glsl"

layout(constant_id = 0) const int kBoxKind = 0;           // 0: bspline, 1: box
layout(constant_id = 1) const int kInverseSolidAngle = 0; // 0: weigh by the solid angle, 1: by its inverse
// The workgroup's size: 256, or the device's limit where that is lower (Vulkan guarantees 128). The
// loops stride by it; the border's 24 corners need 24 lanes.
layout(local_size_x_id = 2, local_size_x = 256) in;

layout(push_constant) uniform Params {
    int faceSize;  // S_0
    int level;     // the first mip written (face size PROBE_PYRAMID_TAIL_SIZE or less), from mip level - 1
    int lastLevel; // the last mip written
    uint window;   // PROBE_EXACT_TAIL: the first texel of the window bound at binding 0
} params;

vec3 tailAboveBilinear(int face, float x, float y, int fineSize) {
#ifdef PROBE_EXACT_TAIL
    return sampleBilinear(params.faceSize, params.level - 1, face, x, y);
#else
    vec2 uv = texelToFaceUv(x, y, fineSize);
    return pyramidRead(faceUvToCubePoint(face, uv.x, uv.y), 0.0);
#endif
}
vec3 tailAboveTexel(int face, int i, int j, int fineSize) {
#ifdef PROBE_EXACT_TAIL
    return pyramidTexel(pyramidLevelFirst(params.faceSize, params.level - 1) + pyramidTexelIndex(face, i, j, fineSize));
#else
    return pyramidRead(texelCubePoint(face, i, j, fineSize), 0.0); // at the centre: the texel
#endif
}
#include "pyramid_tail.glsl"

vec3 probeSampleFine(int face, float x, float y, int fineSize) { return tailSampleFine(face, x, y, fineSize); }
#include "pyramid_bspline.glsl"
vec3 probeFineTexel(int face, int i, int j, int fineSize) { return tailFineTexel(face, i, j, fineSize); }
#include "pyramid_box.glsl"

void main() {
    batchCube = int(gl_WorkGroupID.z); // a workgroup per cube of a batch
    buildTail(params.faceSize, params.level, params.lastLevel, 0, params.window);
}
