// Pass 1 with exact sampling: one level of the bordered pyramid buffer, mirroring
// core/src/pyramid.cpp. Level 0 is the source, read texel by texel from the source cube. A coarser
// level comes from the finer one:
// bspline: pyramid_bspline.glsl, its bilinear taps seamless through the border.
// box: pyramid_box.glsl, the 2x2 children on the same face.
// A border texel is the adjacent face's texel (probe::texelNeighbour), computed here again rather
// than copied, so one dispatch with no barrier writes a level's faces and edges (or those of the
// faces in the window of the buffer bound: buffers.glsl). A border corner, which has no counterpart,
// holds the average of the three texels that meet there (the face's own corner texel and the two
// border texels beside it), what footprint.glsl needs: the last workgroup of the dispatch to finish
// writes the corners, once every other has stored its texels (workgroup_count.glsl; one counter, since a
// window's faces may span cubes): no dispatch and barrier of their own.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PROBE_PYRAMID_READBACK
#include "probe/shared_constants.h"
#include "images.glsl"
#include "footprint.glsl"
#include "workgroup_count.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE) in;

// The pyramid's settings, fixed per pipeline so that the other paths are compiled out.
layout(constant_id = 0) const int kBoxKind = 0;           // 0: bspline, 1: box
layout(constant_id = 1) const int kInverseSolidAngle = 0; // 0: weigh by the solid angle, 1: by its inverse

layout(push_constant) uniform Params {
    int faceSize;  // S_0
    int level;     // the level written: 0 (the source) to log2(S_0)
    int firstFace; // the faces written: layers of a batch's cubes (batch.glsl)
    int faceCount;
    uint window; // the first texel of the window bound at binding 0
} params;

vec3 probeSampleFine(int face, float x, float y, int fineSize) { return sampleBilinear(params.faceSize, params.level - 1, face, x, y); }
#include "pyramid_bspline.glsl"
vec3 probeFineTexel(int face, int i, int j, int fineSize) {
    return pyramidTexel(pyramidLevelFirst(params.faceSize, params.level - 1) + pyramidTexelIndex(face, i, j, fineSize));
}
#include "pyramid_box.glsl"

// The value of texel t (inside its face) of the level written.
vec3 levelTexel(ivec3 t, int size) {
    if (params.level == 0) return sourceTexel(texelCubePoint(t.x, t.y, t.z, size));
    if (kBoxKind == 0) return pyramidBspline(t.x, t.y, t.z, 2 * size, kInverseSolidAngle != 0);
    return pyramidBox(t.x, t.y, t.z, 2 * size, levelOffset(params.faceSize, params.level - 1), kInverseSolidAngle != 0);
}

// Every texel of each face of the window and its border; a border corner gets the face's own corner
// texel, which the corners then replace.
void storeTexel(uint index, int size) {
    int row = size + 2, perFace = row * row;
    if (index >= uint(params.faceCount * perFace)) return;
    int layer = params.firstFace + int(index) / perFace, face = layer % 6, k = int(index) % perFace;
    batchCube = layer / 6;
    int i = k % row - 1, j = k / row - 1;
    bool insideI = i >= 0 && i < size, insideJ = j >= 0 && j < size;
    int ci = clamp(i, 0, size - 1), cj = clamp(j, 0, size - 1);
    bool edge = insideI != insideJ;
    vec3 value = levelTexel(edge ? texelAcrossEdge(face, i, j, size) : ivec3(face, ci, cj), size);
    storePyramid(pyramidLevelFirst(params.faceSize, params.level) + pyramidTexelIndex(face, i, j, size), params.window, value);
}

vec3 storedTexel(uint first, int face, int i, int j, int size) {
    return pyramid[first + pyramidTexelIndex(face, i, j, size) - params.window].rgb;
}

void main() {
    int size = params.faceSize >> params.level;
    storeTexel(invocationIndex(), size);
    memoryBarrierBuffer();
    if (!lastWorkgroup(0u)) return;
    for (uint index = gl_LocalInvocationIndex; index < uint(4 * params.faceCount); index += gl_WorkGroupSize.x) {
        int layer = params.firstFace + int(index) / 4, face = layer % 6, corner = int(index) % 4;
        batchCube = layer / 6;
        int i = (corner & 1) != 0 ? size : -1, j = (corner & 2) != 0 ? size : -1;
        int ci = clamp(i, 0, size - 1), cj = clamp(j, 0, size - 1);
        uint first = pyramidLevelFirst(params.faceSize, params.level);
        vec3 value =
            (storedTexel(first, face, ci, cj, size) + storedTexel(first, face, i, cj, size) + storedTexel(first, face, ci, j, size)) *
            (1.0 / 3.0);
        storePyramid(first + pyramidTexelIndex(face, i, j, size), params.window, value);
    }
}
