// Pass 1 with hardware sampling: one mip of the pyramid cube image, the arithmetic of pyramid.comp
// with the sampler's seamless bilinear reads in place of the bordered buffer's. Level 0 is the
// source, texel by texel. A coarser level comes from the finer one, bound alone as pyramidCube:
// bspline: pyramid_bspline.glsl, each tap one read of the sampler: across a face edge it reads the
// adjacent face, at a cube corner it follows the Vulkan rule.
// box: pyramid_box.glsl, the 2x2 children on the same face, each read at its centre.
// With kFromSource the dispatch writes mips 0 and 1 at once, both from the source (which the sampler
// cannot filter linearly on every device: its bilinear reads are footprint.glsl's arithmetic over its
// texels), saving a dispatch and a barrier. With PROBE_PYRAMID_FINISH the last run's dispatch also
// builds the tail (pyramid_finish.glsl).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
#include "cube.glsl"
#include "images.glsl"
#include "probe/shared_constants.h"
#include "footprint.glsl"
#include "source_footprint.glsl"

#ifdef PROBE_PYRAMID_FINISH
// The last workgroup builds the tail: 256 lanes, or the device's limit where that is lower (Vulkan
// guarantees 128), as the tail's own dispatch (pyramid_tail.comp).
layout(local_size_x_id = 3, local_size_x = 256) in;
#else
layout(local_size_x = PROBE_WORKGROUP_SIZE) in;
#endif

layout(constant_id = 0) const int kBoxKind = 0;           // 0: bspline, 1: box
layout(constant_id = 1) const int kInverseSolidAngle = 0; // 0: weigh by the solid angle, 1: by its inverse
layout(constant_id = 2) const int kFromSource = 0;        // 1: mips 0 and 1 from the source, in one dispatch

layout(push_constant) uniform Params {
    int faceSize;  // S_0
    int level;     // the mip written: 0 (the source) to log2(S_0)
    int tailLevel; // PROBE_PYRAMID_FINISH: the tail's first mip (0: none), to lastLevel
    int lastLevel;
} params;

#ifdef PROBE_PYRAMID_FINISH
#include "pyramid_finish.glsl"
#endif

// The fine level at face coordinates (u, v) of `face`.
vec3 fine(int face, float u, float v) { return pyramidRead(faceUvToCubePoint(face, u, v), 0.0); }

vec3 probeSampleFine(int face, float x, float y, int fineSize) {
#ifdef PROBE_PYRAMID_FINISH
    if (finishing) return tailSampleFine(face, x, y, fineSize);
#endif
    if (kFromSource != 0) return sourceBilinear(face, x, y, fineSize);
    vec2 uv = texelToFaceUv(x, y, fineSize);
    return fine(face, uv.x, uv.y);
}
#include "pyramid_bspline.glsl"
// A child texel, read at its centre, where the bilinear weights are 1, 0, 0, 0.
vec3 probeFineTexel(int face, int i, int j, int fineSize) {
#ifdef PROBE_PYRAMID_FINISH
    if (finishing) return tailFineTexel(face, i, j, fineSize);
#endif
    if (kFromSource != 0) return sourceTexel(texelCubePoint(face, i, j, fineSize));
    return fine(face, texelCentreUv(i, fineSize), texelCentreUv(j, fineSize));
}
#include "pyramid_box.glsl"

// The texel of invocation `index` (mip 1's follow mip 0's with kFromSource), if it has one.
void buildTexel(uint index) {
    int level = params.level, size = params.faceSize >> level;
    if (kFromSource != 0 && index >= 6u * uint(size * size)) {
        index -= 6u * uint(size * size);
        level = 1;
        size /= 2;
    }
    if (index >= 6u * uint(size * size)) return;
    ivec3 t = texelCoordinates(index, size); // (i, j, face)
    vec3 value;
    if (level == 0) value = sourceTexel(texelCubePoint(t.z, t.x, t.y, size));
    else if (kBoxKind == 0) value = pyramidBspline(t.z, t.x, t.y, 2 * size, kInverseSolidAngle != 0);
    else value = pyramidBox(t.z, t.x, t.y, 2 * size, levelOffset(params.faceSize, level - 1), kInverseSolidAngle != 0);
    storePyramidMip(level - params.level, t, value);
}

void main() {
    batchCube = int(gl_WorkGroupID.z); // a layer of workgroups per cube of a batch
    // invocationIndex() with this shader's lanes.
    buildTexel(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x);
#ifdef PROBE_PYRAMID_FINISH
    finishPyramid(params.faceSize, params.level, params.tailLevel, params.lastLevel);
#endif
}
