// Pass 1's small mips in one workgroup (per cube of a batch): mips firstLevel (face size
// PROBE_PYRAMID_TAIL_SIZE or less) to lastLevel, where a dispatch per mip would pay a barrier each
// for a few hundred texels or fewer. The first mip reads the one above through the includer's
// functions; each later one reads the mip before from shared memory, which keeps it with a one-texel
// border per face as the exact path's buffer does (pyramid.comp) and reads it
// with that path's arithmetic (footprint.glsl). Hardware sampling stores each mip's faces to the
// pyramid image; exact sampling (PROBE_EXACT_TAIL) each mip's bordered texels, border and corners
// included, to the buffer, the same values pyramid.comp writes. Shared by
// pyramid_tail.comp (the tail's own dispatch) and pyramid_finish.glsl (the last workgroup of a run's
// dispatch). The includer defines kBoxKind and kInverseSolidAngle and, before it includes this:
//   vec3 tailAboveBilinear(int face, float x, float y, int fineSize)  a seamless bilinear read of
//     the mip above the first one, at fine-texel coordinates (x, y) of `face`
//   vec3 tailAboveTexel(int face, int i, int j, int fineSize)  texel (i, j) of `face` of that mip
// and reads the finer mip through tailSampleFine and tailFineTexel in its probeSampleFine and
// probeFineTexel (pyramid_bspline.glsl, pyramid_box.glsl), which it includes after this.
#ifndef PROBE_PYRAMID_TAIL_GLSL
#define PROBE_PYRAMID_TAIL_GLSL

#include "buffers.glsl"
#include "cube.glsl"
#include "footprint.glsl"
#include "images.glsl"
#include "probe/shared_constants.h"

#if PROBE_PYRAMID_TAIL_SIZE != 8
#error "the shared texels hold two bordered mips from 8x8 down"
#endif

vec3 pyramidBspline(int face, int i, int j, int fineSize, bool inverseSolidAngle);
vec3 pyramidBox(int face, int i, int j, int fineSize, uint firstGeometry, bool inverseSolidAngle);

// Two bordered mips, the one read and the one written: the first mip written at 0, the next after
// it, the one after that at 0 again.
const int kTailFirstTexels = 6 * (PROBE_PYRAMID_TAIL_SIZE + 2) * (PROBE_PYRAMID_TAIL_SIZE + 2);
const int kTailSecondTexels = 6 * (PROBE_PYRAMID_TAIL_SIZE / 2 + 2) * (PROBE_PYRAMID_TAIL_SIZE / 2 + 2);
shared vec3 tailTexels[kTailFirstTexels + kTailSecondTexels];

// Where the finer mip starts in tailTexels; -1 while it is the mip above the tail's first.
int fineFirst = -1;

vec3 tailSampleFine(int face, float x, float y, int fineSize) {
    if (fineFirst < 0) return tailAboveBilinear(face, x, y, fineSize);
    vec2 f;
    uint t = uint(fineFirst) + bilinearFootprint(fineSize, face, x, y, f);
    uint row = uint(fineSize + 2);
    return bilinearBlend(f, tailTexels[t], tailTexels[t + 1u], tailTexels[t + row], tailTexels[t + row + 1u]);
}

vec3 tailFineTexel(int face, int i, int j, int fineSize) {
    if (fineFirst < 0) return tailAboveTexel(face, i, j, fineSize);
    return tailTexels[uint(fineFirst) + pyramidTexelIndex(face, i, j, fineSize)];
}

// Mips firstLevel to lastLevel of the pyramid whose level 0 has face size faceSize. Hardware sampling
// stores mip k to pyramidMips element firstElement + k - firstLevel; exact sampling to the buffer's
// window that starts at texel `window`.
void buildTail(int faceSize, int firstLevel, int lastLevel, int firstElement, uint window) {
    uint lane = gl_LocalInvocationIndex, lanes = gl_WorkGroupSize.x;
    fineFirst = -1;
    for (int level = firstLevel; level <= lastLevel; ++level) {
        int size = faceSize >> level;
        uint first = ((level - firstLevel) & 1) == 0 ? 0u : uint(kTailFirstTexels);
        // The faces: stored to the mip and kept.
        for (uint index = lane; index < 6u * uint(size * size); index += lanes) {
            ivec3 t = texelCoordinates(index, size); // (i, j, face)
            vec3 value;
            if (kBoxKind == 0) value = pyramidBspline(t.z, t.x, t.y, 2 * size, kInverseSolidAngle != 0);
            else value = pyramidBox(t.z, t.x, t.y, 2 * size, levelOffset(faceSize, level - 1), kInverseSolidAngle != 0);
#ifndef PROBE_EXACT_TAIL
            value = clamp(value, -PROBE_PYRAMID_MAX, PROBE_PYRAMID_MAX);
            storePyramidMip(firstElement + level - firstLevel, t, value);
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
        uint row = uint(size + 2), levelFirst = pyramidLevelFirst(faceSize, level);
        for (uint index = lane; index < 6u * row * row; index += lanes) storePyramid(levelFirst + index, window, tailTexels[first + index]);
#endif
        fineFirst = int(first);
    }
}

#endif
