// Pass 1 with hardware sampling, its tail in the last run's dispatch, in the manner of AMD's
// single-pass downsampler (SPD): the dispatch of the last run of mips (FilterPlan::pyramidMipRuns)
// also builds the tail, the mips from face size PROBE_PYRAMID_TAIL_SIZE down. Each workgroup, once
// its texels are stored, counts itself in its cube's counter (workgroup_count.glsl); the last of a
// cube's workgroups, when every other one's texels are stored (the images are coherent), builds the
// tail in shared memory (pyramid_tail.glsl) with the workgroup's lanes (256 where the device allows,
// as the tail's own dispatch has), its first mip from the run's last through the image, read with
// the bordered buffer's rule: across a face edge the adjacent face's texel, at a cube corner the
// average of the other three. The tail's dispatch and its barrier are saved. Needs
// PROBE_PYRAMID_FINISH (images.glsl: the run's mips and the tail's, readable); the includer defines
// kBoxKind and kInverseSolidAngle.
#ifndef PROBE_PYRAMID_FINISH_GLSL
#define PROBE_PYRAMID_FINISH_GLSL

#include "batch.glsl"
#include "cube.glsl"
#include "footprint.glsl"
#include "images.glsl"
#include "workgroup_count.glsl"

#ifndef PROBE_PYRAMID_FINISH
#error "pyramid_finish.glsl reads the mips it builds from: PROBE_PYRAMID_FINISH"
#endif

bool finishing = false; // the last workgroup, building the tail: reads go through the tail's functions
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

// Called by every invocation at the end of main(), after the workgroup's stores, with the run's first
// mip (pyramidMips element 0) and the tail's mips (firstLevel 0: none), which follow the run's.
void finishPyramid(int faceSize, int runFirst, int firstLevel, int lastLevel) {
    if (firstLevel <= 0) return;
    memoryBarrierImage();
    if (!lastWorkgroup(uint(batchCube))) return; // a counter per cube of the batch
    finishing = true;
    finishAbove = firstLevel - 1 - runFirst;
    buildTail(faceSize, firstLevel, lastLevel, firstLevel - runFirst, 0u);
}

#endif
