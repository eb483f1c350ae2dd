// Pass 1 with hardware sampling, two mips in one dispatch: mips L and L + 1, a workgroup per 8x8 tile
// of mip L + 1 of one face (a layer of workgroups per cube of a batch). The workgroup builds mip L over
// what the tile's B-spline reads, its 16x16 texels and a ring of one texel: across a face edge the
// adjacent face's texel, at a cube corner the average of the other three (the bordered buffer's rule,
// pyramid.comp), each as pyramid_image.comp builds it. It keeps that in shared memory and reads mip
// L + 1's taps there with footprint.glsl's arithmetic, as pyramid_tail.comp reads the mips it keeps.
// With kFromSource, the first dispatch: mips 0, 1 and 2, mip 1 from the source (L = 1). Mip L is
// pyramid_image.comp's bit for bit; mip L + 1 is read with exact bilinear weights from mip L kept in
// float, where pyramid_image.comp reads it through the sampler from the pyramid's format. A dispatch
// and a barrier fewer for each pair. With PROBE_PYRAMID_FINISH the last run's dispatch also builds
// the tail (pyramid_finish.glsl).
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
layout(constant_id = 2) const int kFromSource = 0;        // 1: mips 0 to 2, from the source

layout(push_constant) uniform Params {
    int faceSize;  // S_0
    int level;     // L: mip L and mip L + 1 (of 16x16 or more) are built, from mip L - 1 bound as pyramidCube, or from the source
    int tailLevel; // PROBE_PYRAMID_FINISH: the tail's first mip (0: none), to lastLevel
    int lastLevel;
} params;

const int kTile = 8;               // mip L + 1 texels per side of a tile
const int kRegion = 2 * kTile + 2; // mip L texels per side of what its B-spline reads
#ifdef PROBE_PYRAMID_FINISH
#include "pyramid_finish.glsl"
// The region lives in the tail's shared texels, which the last workgroup takes over after it: both
// within the 16 KiB of shared memory that every device offers.
#define region tailTexels
#else
shared vec3 region[kRegion * kRegion];
#endif

// Mip L texel (i, j) of the region around the tile, which starts at (regionI, regionJ) of mip L.
int regionI, regionJ;
bool fromRegion = false; // mip L + 1's reads: from the region; else mip L's, from mip L - 1
vec3 regionTexel(int i, int j) { return region[(j - regionJ) * kRegion + (i - regionI)]; }

vec3 probeSampleFine(int face, float x, float y, int fineSize) {
#ifdef PROBE_PYRAMID_FINISH
    if (finishing) return tailSampleFine(face, x, y, fineSize);
#endif
    if (fromRegion) {
        vec2 f;
        ivec2 t = footprintFirst(fineSize, x, y, f);
        return bilinearBlend(f, regionTexel(t.x, t.y), regionTexel(t.x + 1, t.y), regionTexel(t.x, t.y + 1),
                             regionTexel(t.x + 1, t.y + 1));
    }
    if (kFromSource != 0) return sourceBilinear(face, x, y, fineSize);
    vec2 uv = texelToFaceUv(x, y, fineSize);
    return pyramidRead(faceUvToCubePoint(face, uv.x, uv.y), 0.0);
}
#include "pyramid_bspline.glsl"
vec3 probeFineTexel(int face, int i, int j, int fineSize) {
#ifdef PROBE_PYRAMID_FINISH
    if (finishing) return tailFineTexel(face, i, j, fineSize);
#endif
    if (fromRegion) return regionTexel(i, j);
    if (kFromSource != 0) return sourceTexel(texelCubePoint(face, i, j, fineSize));
    return pyramidRead(faceUvToCubePoint(face, texelCentreUv(i, fineSize), texelCentreUv(j, fineSize)), 0.0); // the texel
}
#include "pyramid_box.glsl"

// Texel (i, j) of `face` of mip `level`, from the mip above.
vec3 pyramidTexelFrom(int face, int i, int j, int level) {
    int fineSize = params.faceSize >> (level - 1);
    if (kBoxKind == 0) return pyramidBspline(face, i, j, fineSize, kInverseSolidAngle != 0);
    return pyramidBox(face, i, j, fineSize, levelOffset(params.faceSize, level - 1), kInverseSolidAngle != 0);
}

// The mip in pyramidMips element 0: mip 0 with kFromSource, else mip params.level.
int runFirst() { return kFromSource != 0 ? 0 : params.level; }

// Mip params.level + k (k from -1: the source's mip 0) into pyramidMips.
void storeMip(int k, ivec3 texel, vec3 value) { storePyramidMip(params.level + k - runFirst(), texel, value); }

void main() {
    uint lane = gl_LocalInvocationIndex, lanes = gl_WorkGroupSize.x;
    batchCube = int(gl_WorkGroupID.z);
    int level = params.level, size = params.faceSize >> level, tiles = (size / 2) / kTile; // tiles per face side
    int face = int(gl_WorkGroupID.x) / (tiles * tiles), tile = int(gl_WorkGroupID.x) % (tiles * tiles);
    int tileI = tile % tiles * kTile, tileJ = tile / tiles * kTile; // the tile's first mip L + 1 texel
    regionI = 2 * tileI - 1;
    regionJ = 2 * tileJ - 1;

    // With kFromSource, mip 0: the source texels under the tile.
    if (kFromSource != 0)
        for (uint index = lane; index < uint(16 * kTile * kTile); index += lanes) {
            int i = 4 * tileI + int(index) % (4 * kTile), j = 4 * tileJ + int(index) / (4 * kTile);
            storeMip(-1, ivec3(i, j, face), sourceTexel(texelCubePoint(face, i, j, params.faceSize)));
        }
    // Mip L over the region; its texels under the tile are stored. A texel off the face is the adjacent
    // face's; a corner, off both of the face's axes, comes after the texels it averages.
    for (uint index = lane; index < uint(kRegion * kRegion); index += lanes) {
        int i = regionI + int(index) % kRegion, j = regionJ + int(index) / kRegion;
        bool outI = i < 0 || i >= size, outJ = j < 0 || j >= size;
        if (outI && outJ) continue;
        ivec3 t = outI || outJ ? texelAcrossEdge(face, i, j, size) : ivec3(face, i, j);
        vec3 value = clamp(pyramidTexelFrom(t.x, t.y, t.z, level), -PROBE_PYRAMID_MAX, PROBE_PYRAMID_MAX);
        region[index] = value;
        if (i >= 2 * tileI && i < 2 * (tileI + kTile) && j >= 2 * tileJ && j < 2 * (tileJ + kTile)) storeMip(0, ivec3(i, j, face), value);
    }
    memoryBarrierShared();
    barrier();
    if (lane < 4u) { // the region's corners, where they lie off both axes: the average of the other three
        int i = (lane & 1u) != 0u ? regionI + kRegion - 1 : regionI, j = (lane & 2u) != 0u ? regionJ + kRegion - 1 : regionJ;
        if ((i < 0 || i >= size) && (j < 0 || j >= size)) {
            int ci = clamp(i, 0, size - 1), cj = clamp(j, 0, size - 1);
            region[(j - regionJ) * kRegion + (i - regionI)] = (regionTexel(ci, cj) + regionTexel(i, cj) + regionTexel(ci, j)) * (1.0 / 3.0);
        }
    }
    memoryBarrierShared();
    barrier();
    // Mip L + 1: the tile, from the region.
    fromRegion = true;
    for (uint index = lane; index < uint(kTile * kTile); index += lanes) {
        int i = tileI + int(index) % kTile, j = tileJ + int(index) / kTile;
        storeMip(1, ivec3(i, j, face), pyramidTexelFrom(face, i, j, level + 1));
    }
#ifdef PROBE_PYRAMID_FINISH
    finishPyramid(params.faceSize, runFirst(), params.tailLevel, params.lastLevel);
#endif
}
