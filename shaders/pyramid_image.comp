// Pass 1 with hardware sampling: one mip of the pyramid cube image, the arithmetic of pyramid.comp
// with the sampler's seamless bilinear reads in place of the bordered buffer's. Level 0 is the
// source, texel by texel. A coarser level comes from the finer one, bound alone as pyramidCube:
// bspline: pyramid_bspline.glsl, each tap one read of the sampler: across a face edge it reads the
// adjacent face, at a cube corner it follows the Vulkan rule.
// box: pyramid_box.glsl, the 2x2 children on the same face, each read at its centre.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
#include "cube.glsl"
#include "images.glsl"
#include "probe/shared_constants.h"
#include "footprint.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE) in;

layout(constant_id = 0) const int kBoxKind = 0;           // 0: bspline, 1: box
layout(constant_id = 1) const int kInverseSolidAngle = 0; // 0: weigh by the solid angle, 1: by its inverse

layout(push_constant) uniform Params {
    int faceSize; // S_0
    int level;    // the mip written: 0 (the source) to log2(S_0)
} params;

// The fine level at face coordinates (u, v) of `face`.
vec3 fine(int face, float u, float v) { return pyramidRead(faceUvToCubePoint(face, u, v), 0.0); }

vec3 probeSampleFine(int face, float x, float y, int fineSize) {
    vec2 uv = texelToFaceUv(x, y, fineSize);
    return fine(face, uv.x, uv.y);
}
#include "pyramid_bspline.glsl"
// A child texel, read at its centre, where the bilinear weights are 1, 0, 0, 0.
vec3 probeFineTexel(int face, int i, int j, int fineSize) { return fine(face, texelCentreUv(i, fineSize), texelCentreUv(j, fineSize)); }
#include "pyramid_box.glsl"

void main() {
    int level = params.level, size = params.faceSize >> level;
    uint index = invocationIndex();
    batchCube = int(gl_WorkGroupID.z); // a layer of workgroups per cube of a batch
    if (index >= 6u * uint(size * size)) return;
    ivec3 t = texelCoordinates(index, size); // (i, j, face)
    vec3 value;
    if (level == 0) value = sourceTexel(texelCubePoint(t.z, t.x, t.y, size));
    else if (kBoxKind == 0) value = pyramidBspline(t.z, t.x, t.y, 2 * size, kInverseSolidAngle != 0);
    else value = pyramidBox(t.z, t.x, t.y, 2 * size, levelOffset(params.faceSize, level - 1), kInverseSolidAngle != 0);
    storePyramidMip(0, t, value);
}
