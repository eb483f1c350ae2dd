// Pass 1, its small mips in one dispatch: one workgroup (per cube of a batch) builds mips params.level
// (face size PROBE_PYRAMID_TAIL_SIZE or less) to params.lastLevel, where a dispatch per mip would pay
// a barrier each for a few hundred texels or fewer. The first mip reads the one above through the
// sampler, as pyramid_image.comp does (with PROBE_EXACT_TAIL, exact sampling's: from the bordered
// buffer, as pyramid.comp does); each later one reads the mip before from shared memory, which keeps
// it with a one-texel border per face as the exact path's buffer does (pyramid.comp) and reads it
// with that path's arithmetic (footprint.glsl). Hardware sampling stores each mip's faces to the
// pyramid image; exact sampling each mip's bordered texels, border and corners included, to the
// buffer, the same values pyramid.comp writes.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
#include "cube.glsl"
#include "images.glsl"
#include "probe/shared_constants.h"
#include "footprint.glsl"

#if PROBE_PYRAMID_TAIL_SIZE != 8
#error "pyramidMips (images.glsl) holds the four mips from 8x8 down"
#endif

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

// Two bordered mips, the one read and the one written: the first mip written at 0, the next after
// it, the one after that at 0 again.
const int kFirstTexels = 6 * (PROBE_PYRAMID_TAIL_SIZE + 2) * (PROBE_PYRAMID_TAIL_SIZE + 2);
const int kSecondTexels = 6 * (PROBE_PYRAMID_TAIL_SIZE / 2 + 2) * (PROBE_PYRAMID_TAIL_SIZE / 2 + 2);
shared vec3 tailTexels[kFirstTexels + kSecondTexels];

// Where the finer mip starts in tailTexels; -1 while it is the mip above the tail, in pyramidCube.
int fineFirst = -1;

vec3 probeSampleFine(int face, float x, float y, int fineSize) {
    if (fineFirst < 0) {
#ifdef PROBE_EXACT_TAIL
        return sampleBilinear(params.faceSize, params.level - 1, face, x, y);
#else
        vec2 uv = texelToFaceUv(x, y, fineSize);
        return pyramidRead(faceUvToCubePoint(face, uv.x, uv.y), 0.0);
#endif
    }
    vec2 f;
    uint t = uint(fineFirst) + bilinearFootprint(fineSize, face, x, y, f);
    uint row = uint(fineSize + 2);
    return bilinearBlend(f, tailTexels[t], tailTexels[t + 1u], tailTexels[t + row], tailTexels[t + row + 1u]);
}
#include "pyramid_bspline.glsl"
vec3 probeFineTexel(int face, int i, int j, int fineSize) {
#ifdef PROBE_EXACT_TAIL
    if (fineFirst < 0)
        return pyramidTexel(pyramidLevelFirst(params.faceSize, params.level - 1) + pyramidTexelIndex(face, i, j, fineSize));
#else
    if (fineFirst < 0) return pyramidRead(texelCubePoint(face, i, j, fineSize), 0.0); // at the centre: the texel
#endif
    return tailTexels[uint(fineFirst) + pyramidTexelIndex(face, i, j, fineSize)];
}
#include "pyramid_box.glsl"

void main() {
    uint lane = gl_LocalInvocationIndex, lanes = gl_WorkGroupSize.x;
    batchCube = int(gl_WorkGroupID.z); // a workgroup per cube of a batch
    for (int level = params.level; level <= params.lastLevel; ++level) {
        int size = params.faceSize >> level;
        uint first = ((level - params.level) & 1) == 0 ? 0u : uint(kFirstTexels);
        // The faces: stored to the mip and kept.
        for (uint index = lane; index < 6u * uint(size * size); index += lanes) {
            ivec3 t = texelCoordinates(index, size); // (i, j, face)
            vec3 value;
            if (kBoxKind == 0) value = pyramidBspline(t.z, t.x, t.y, 2 * size, kInverseSolidAngle != 0);
            else value = pyramidBox(t.z, t.x, t.y, 2 * size, levelOffset(params.faceSize, level - 1), kInverseSolidAngle != 0);
#ifndef PROBE_EXACT_TAIL
            value = pyramidRange(value);
            storePyramidMip(level - params.level, t, value);
#endif
            tailTexels[first + pyramidTexelIndex(t.z, t.x, t.y, size)] = value;
        }
        memoryBarrierShared();
        barrier();
        // The border's edges: the adjacent face's texel (probe::texelNeighbour), as pyramid.comp.
        for (uint index = lane; index < 24u * uint(size); index += lanes) {
            int face = int(index) / (4 * size), side = int(index) / size % 4, k = int(index) % size;
            int i = side == 0 ? -1 : side == 1 ? size : k;
            int j = side == 2 ? -1 : side == 3 ? size : k;
            ivec3 n = texelAcrossEdge(face, i, j, size); // (face, i, j)
            tailTexels[first + pyramidTexelIndex(face, i, j, size)] = tailTexels[first + pyramidTexelIndex(n.x, n.y, n.z, size)];
        }
        memoryBarrierShared();
        barrier();
        // The border's corners: the average of the three texels that meet there, as pyramid.comp.
        if (lane < 24u) {
            int face = int(lane) / 4, corner = int(lane) % 4;
            int i = (corner & 1) != 0 ? size : -1, j = (corner & 2) != 0 ? size : -1;
            int ci = clamp(i, 0, size - 1), cj = clamp(j, 0, size - 1);
            tailTexels[first + pyramidTexelIndex(face, i, j, size)] =
                (tailTexels[first + pyramidTexelIndex(face, ci, cj, size)] + tailTexels[first + pyramidTexelIndex(face, i, cj, size)] +
                 tailTexels[first + pyramidTexelIndex(face, ci, j, size)]) *
                (1.0 / 3.0);
        }
        memoryBarrierShared();
        barrier();
#ifdef PROBE_EXACT_TAIL
        // The bordered mip, laid out in shared memory as in the buffer.
        uint row = uint(size + 2), levelFirst = pyramidLevelFirst(params.faceSize, level);
        for (uint index = lane; index < 6u * row * row; index += lanes)
            storePyramid(levelFirst + index, params.window, tailTexels[first + index]);
#endif
        fineFirst = int(first);
    }
}
