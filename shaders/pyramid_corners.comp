// Pass 1, after each level of pyramid.comp: the four border corners of every face. A border corner
// has no counterpart on the cube; it holds the average of the three texels that meet there (the
// face's own corner texel and the two border texels beside it, which pyramid.comp has just written),
// what footprint.glsl needs. A dispatch of its own rather than a branch in pyramid.comp: a SIMD back
// end such as lavapipe runs a branch's body even where no lane takes it.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE) in;

layout(push_constant) uniform Params {
    int faceSize;  // S_0
    int level;     // the level whose corners are written
    int firstFace; // the faces whose corners are written: layers of a batch's cubes (batch.glsl)
    int faceCount;
    uint window; // the first texel of the window bound at binding 0
} params;

void main() {
    uint index = invocationIndex();
    if (index >= uint(4 * params.faceCount)) return;
    int size = params.faceSize >> params.level;
    int layer = params.firstFace + int(index) / 4, face = layer % 6, corner = int(index) % 4;
    batchCube = layer / 6;
    int i = (corner & 1) != 0 ? size : -1, j = (corner & 2) != 0 ? size : -1;
    int ci = clamp(i, 0, size - 1), cj = clamp(j, 0, size - 1);
    uint first = pyramidLevelFirst(params.faceSize, params.level);
    vec3 value = (pyramidTexel(first + pyramidTexelIndex(face, ci, cj, size)) + pyramidTexel(first + pyramidTexelIndex(face, i, cj, size)) +
                  pyramidTexel(first + pyramidTexelIndex(face, ci, j, size))) *
                 (1.0 / 3.0);
    storePyramid(first + pyramidTexelIndex(face, i, j, size), params.window, value);
}
