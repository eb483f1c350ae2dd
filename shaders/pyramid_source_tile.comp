// Pass 1 with hardware sampling, its first dispatch where the source is 64^2 or larger: mips 0, 1 and
// 2 of the pyramid cube image, all from the source, a workgroup per 8x8 tile of mip 2 of one face
// (a layer of workgroups per cube of a batch). The workgroup builds mip 1 over what the tile's
// B-spline reads, its 16x16 texels and a ring of one texel: across a face edge the adjacent face's
// texel, at a cube corner the average of the other three (the bordered buffer's rule, pyramid.comp),
// each from the source as pyramid_image.comp builds it. It keeps that in shared memory and reads mip
// 2's taps there with footprint.glsl's arithmetic, as pyramid_tail.comp reads the mips it keeps.
// Mips 0 and 1 are pyramid_image.comp's bit for bit; mip 2 is read with exact bilinear weights from
// mip 1 kept in float, where pyramid_image.comp reads it through the sampler from the pyramid's
// format. One dispatch and one barrier fewer than a dispatch for mip 2.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
#include "cube.glsl"
#include "images.glsl"
#include "probe/shared_constants.h"
#include "footprint.glsl"
#include "source_footprint.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE) in;

layout(constant_id = 0) const int kBoxKind = 0;           // 0: bspline, 1: box
layout(constant_id = 1) const int kInverseSolidAngle = 0; // 0: weigh by the solid angle, 1: by its inverse

layout(push_constant) uniform Params {
    int faceSize; // S_0, 64 or larger
} params;

const int kTile = 8;               // mip 2 texels per side of a tile
const int kRegion = 2 * kTile + 2; // mip 1 texels per side of what its B-spline reads
shared vec3 region[kRegion * kRegion];

// Mip 1 texel (i, j) of the region around the tile, which starts at (regionI, regionJ) of mip 1.
int regionI, regionJ;
bool fromRegion = false; // mip 2's reads: from the region; else mip 1's, from the source
vec3 regionTexel(int i, int j) { return region[(j - regionJ) * kRegion + (i - regionI)]; }

vec3 probeSampleFine(int face, float x, float y, int fineSize) {
    if (!fromRegion) return sourceBilinear(face, x, y, fineSize);
    vec2 f;
    ivec2 t = footprintFirst(fineSize, x, y, f);
    return bilinearBlend(f, regionTexel(t.x, t.y), regionTexel(t.x + 1, t.y), regionTexel(t.x, t.y + 1), regionTexel(t.x + 1, t.y + 1));
}
#include "pyramid_bspline.glsl"
vec3 probeFineTexel(int face, int i, int j, int fineSize) {
    if (!fromRegion) return sourceTexel(texelCubePoint(face, i, j, fineSize));
    return regionTexel(i, j);
}
#include "pyramid_box.glsl"

// Texel (i, j) of `face` of mip `level` (1 or 2), from the level above.
vec3 pyramidTexelFrom(int face, int i, int j, int level) {
    int fineSize = params.faceSize >> (level - 1);
    if (kBoxKind == 0) return pyramidBspline(face, i, j, fineSize, kInverseSolidAngle != 0);
    return pyramidBox(face, i, j, fineSize, levelOffset(params.faceSize, level - 1), kInverseSolidAngle != 0);
}

void storeMip(int mip, ivec3 texel, vec3 value) {
    texel = batchLayer(texel);
    vec4 v = vec4(clamp(value, -PROBE_PYRAMID_MAX, PROBE_PYRAMID_MAX), 1.0);
    if (mip == 0) imageStore(pyramidMips[0], texel, v);
    else if (mip == 1) imageStore(pyramidMips[1], texel, v);
    else imageStore(pyramidMips[2], texel, v);
}

void main() {
    uint lane = gl_LocalInvocationIndex, lanes = gl_WorkGroupSize.x;
    batchCube = int(gl_WorkGroupID.z);
    int size1 = params.faceSize / 2, tiles = params.faceSize / (4 * kTile); // tiles per face side
    int face = int(gl_WorkGroupID.x) / (tiles * tiles), tile = int(gl_WorkGroupID.x) % (tiles * tiles);
    int tileI = tile % tiles * kTile, tileJ = tile / tiles * kTile; // the tile's first mip 2 texel
    regionI = 2 * tileI - 1;
    regionJ = 2 * tileJ - 1;

    // Mip 0: the source texels under the tile.
    for (uint index = lane; index < uint(16 * kTile * kTile); index += lanes) {
        int i = 4 * tileI + int(index) % (4 * kTile), j = 4 * tileJ + int(index) / (4 * kTile);
        storeMip(0, ivec3(i, j, face), sourceTexel(texelCubePoint(face, i, j, params.faceSize)));
    }
    // Mip 1 over the region; its texels under the tile are stored. A texel off the face is the adjacent
    // face's; a corner, off both of the face's axes, comes after the texels it averages.
    for (uint index = lane; index < uint(kRegion * kRegion); index += lanes) {
        int i = regionI + int(index) % kRegion, j = regionJ + int(index) / kRegion;
        bool outI = i < 0 || i >= size1, outJ = j < 0 || j >= size1;
        if (outI && outJ) continue;
        ivec3 t = outI || outJ ? texelAcrossEdge(face, i, j, size1) : ivec3(face, i, j);
        vec3 value = clamp(pyramidTexelFrom(t.x, t.y, t.z, 1), -PROBE_PYRAMID_MAX, PROBE_PYRAMID_MAX);
        region[index] = value;
        if (i >= 2 * tileI && i < 2 * (tileI + kTile) && j >= 2 * tileJ && j < 2 * (tileJ + kTile)) storeMip(1, ivec3(i, j, face), value);
    }
    memoryBarrierShared();
    barrier();
    if (lane < 4u) { // the region's corners, where they lie off both axes: the average of the other three
        int i = (lane & 1u) != 0u ? regionI + kRegion - 1 : regionI, j = (lane & 2u) != 0u ? regionJ + kRegion - 1 : regionJ;
        if ((i < 0 || i >= size1) && (j < 0 || j >= size1)) {
            int ci = clamp(i, 0, size1 - 1), cj = clamp(j, 0, size1 - 1);
            region[(j - regionJ) * kRegion + (i - regionI)] = (regionTexel(ci, cj) + regionTexel(i, cj) + regionTexel(ci, j)) * (1.0 / 3.0);
        }
    }
    memoryBarrierShared();
    barrier();
    // Mip 2: the tile, from the region.
    fromRegion = true;
    for (uint index = lane; index < uint(kTile * kTile); index += lanes) {
        int i = tileI + int(index) % kTile, j = tileJ + int(index) / kTile;
        storeMip(2, ivec3(i, j, face), pyramidTexelFrom(face, i, j, 2));
    }
}
