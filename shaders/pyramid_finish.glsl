// Pass 1 with hardware sampling in fewer dispatches, in the manner of AMD's single-pass downsampler
// (SPD): the dispatch of the last run of mips (FilterPlan::pyramidMipRuns) also builds every mip below
// it, down to the depth. Each workgroup, once its texels are stored, counts itself in its cube's
// counter; the last of a cube's workgroups to do so, when every other one's texels are stored (the
// images are coherent), builds the rest: a mip of face size 2 * PROBE_PYRAMID_TAIL_SIZE texel by
// texel from the image to the image, then the tail in shared memory (pyramid_tail.glsl), its first
// mip read from the image. Reads of the image take the bordered buffer's rule: across a face edge the
// adjacent face's texel, at a cube corner the average of the other three. The last workgroup sets
// the counter back to 0 for the next recording. The tail's dispatch and barrier are saved, and the
// mip above the tail's. Needs PROBE_PYRAMID_FINISH (images.glsl: every mip of the run and below it,
// readable); the includer defines kBoxKind and kInverseSolidAngle.
#ifndef PROBE_PYRAMID_FINISH_GLSL
#define PROBE_PYRAMID_FINISH_GLSL

#include "batch.glsl"
#include "cube.glsl"
#include "footprint.glsl"
#include "images.glsl"

#ifndef PROBE_PYRAMID_FINISH
#error "pyramid_finish.glsl reads the mips it builds from: PROBE_PYRAMID_FINISH"
#endif

// A counter per cube of the batch, 0 between dispatches.
layout(std430, set = 0, binding = 9) coherent buffer PyramidCounters { uint pyramidCounters[]; };

bool finishing = false; // the last workgroup, building the mips below the run: reads go through here
int finishAbove = 0;    // the pyramidMips element of the mip the tail's first mip reads

// Texel (i, j) of `face` of the mip at element finishAbove (face size `size`), i and j in [-1, size].
vec3 finishEdgeTexel(int face, int i, int j, int size) {
    ivec3 t = i < 0 || i >= size || j < 0 || j >= size ? texelAcrossEdge(face, i, j, size) : ivec3(face, i, j);
    return loadPyramidMip(finishAbove, ivec3(t.y, t.z, t.x));
}
vec3 finishTexel(int face, int i, int j, int size) {
    bool outI = i < 0 || i >= size, outJ = j < 0 || j >= size;
    if (!(outI && outJ)) return finishEdgeTexel(face, i, j, size);
    int ci = clamp(i, 0, size - 1), cj = clamp(j, 0, size - 1);
    return (finishEdgeTexel(face, ci, cj, size) + finishEdgeTexel(face, i, cj, size) + finishEdgeTexel(face, ci, j, size)) * (1.0 / 3.0);
}

vec3 tailAboveBilinear(int face, float x, float y, int fineSize) {
    vec2 f;
    ivec2 t = footprintFirst(fineSize, x, y, f);
    return bilinearBlend(f, finishTexel(face, t.x, t.y, fineSize), finishTexel(face, t.x + 1, t.y, fineSize),
                         finishTexel(face, t.x, t.y + 1, fineSize), finishTexel(face, t.x + 1, t.y + 1, fineSize));
}
vec3 tailAboveTexel(int face, int i, int j, int fineSize) { return finishEdgeTexel(face, i, j, fineSize); }
#include "pyramid_tail.glsl"

shared uint finishCount;

// Called by every invocation at the end of main(), after the workgroup's stores, with the run's first
// mip (pyramidMips element 0) and the mips to build below it (firstLevel 0: none). The last workgroup
// of the cube builds them.
void finishPyramid(int faceSize, int runFirst, int firstLevel, int lastLevel) {
    if (firstLevel <= 0) return;
    uint lane = gl_LocalInvocationIndex, lanes = gl_WorkGroupSize.x;
    memoryBarrierImage();
    barrier();
    if (lane == 0u) finishCount = atomicAdd(pyramidCounters[batchCube], 1u);
    barrier();
    if (finishCount + 1u != gl_NumWorkGroups.x * gl_NumWorkGroups.y) return;
    finishing = true;
    int level = firstLevel;
    finishAbove = level - 1 - runFirst;
    // Above the tail: from the image, to the image.
    for (; level <= lastLevel && (faceSize >> level) > PROBE_PYRAMID_TAIL_SIZE; ++level) {
        int size = faceSize >> level;
        for (uint index = lane; index < 6u * uint(size * size); index += lanes) {
            ivec3 t = texelCoordinates(index, size); // (i, j, face)
            vec3 value;
            if (kBoxKind == 0) value = pyramidBspline(t.z, t.x, t.y, 2 * size, kInverseSolidAngle != 0);
            else value = pyramidBox(t.z, t.x, t.y, 2 * size, levelOffset(faceSize, level - 1), kInverseSolidAngle != 0);
            storePyramidMip(level - runFirst, t, value);
        }
        memoryBarrierImage();
        barrier();
        finishAbove = level - runFirst;
    }
    if (level <= lastLevel) buildTail(faceSize, level, lastLevel, level - runFirst, 0u);
    if (lane == 0u) pyramidCounters[batchCube] = 0u;
}

#endif
