// Bilinear reads of the source cube with the shader's own arithmetic, for pass 1's mips built from
// the source (pyramid_image.comp, pyramid_tile.comp): the sampler cannot filter every source
// format linearly on every device, and the arithmetic is footprint.glsl's over the bordered buffer,
// with the border's texels taken from the source as pyramid.comp stores them.
#ifndef PROBE_SOURCE_FOOTPRINT_GLSL
#define PROBE_SOURCE_FOOTPRINT_GLSL

#include "cube.glsl"
#include "footprint.glsl"
#include "images.glsl"

// Source texel (i, j) of `face`, i and j in [-1, size]: the adjacent face's texel across an edge, and
// at a cube corner, where the footprint's fourth texel does not exist, the average of the other three.
vec3 sourceAt(int face, int i, int j, int size) {
    bool outI = i < 0 || i >= size, outJ = j < 0 || j >= size;
    int ci = clamp(i, 0, size - 1), cj = clamp(j, 0, size - 1);
    if (outI && outJ) {
        ivec3 a = texelAcrossEdge(face, i, cj, size), b = texelAcrossEdge(face, ci, j, size);
        return (sourceTexel(texelCubePoint(face, ci, cj, size)) + sourceTexel(texelCubePoint(a.x, a.y, a.z, size)) +
                sourceTexel(texelCubePoint(b.x, b.y, b.z, size))) *
               (1.0 / 3.0);
    }
    ivec3 t = outI || outJ ? texelAcrossEdge(face, i, j, size) : ivec3(face, i, j);
    return sourceTexel(texelCubePoint(t.x, t.y, t.z, size));
}

// The source (face size `size`) at continuous texel coordinates (x, y) of `face`.
vec3 sourceBilinear(int face, float x, float y, int size) {
    vec2 f;
    ivec2 t = footprintFirst(size, x, y, f);
    return bilinearBlend(f, sourceAt(face, t.x, t.y, size), sourceAt(face, t.x + 1, t.y, size), sourceAt(face, t.x, t.y + 1, size),
                         sourceAt(face, t.x + 1, t.y + 1, size));
}

#endif
