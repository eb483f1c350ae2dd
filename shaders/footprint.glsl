// Seamless bilinear and trilinear reads of the pyramid buffer, mirroring core's
// probe/cube_footprint.h with the shader's own arithmetic: texel coordinates x = (u + 1) / 2 * S
// clamped to [0, S], so the 2x2 footprint lies within a face and its one-texel border, where
// pyramid.comp put what the model reads there: the texel of the adjacent face (probe::texelNeighbour)
// and, at a cube corner, where the footprint's fourth texel does not exist, the Vulkan rule's
// average of the other three (the model gives a third of its weight to each).
#ifndef PROBE_FOOTPRINT_GLSL
#define PROBE_FOOTPRINT_GLSL

#include "buffers.glsl"
#include "cube.glsl"

// The 2x2 footprint of a bilinear read at continuous texel coordinates (x, y) in a face of size
// `size`: its first texel (i, j), each in [-1, size - 1] (the texel after it may lie one step beyond
// the face), and in `f` the weights of its second column and row.
ivec2 footprintFirst(int size, float x, float y, out vec2 f) {
    x = clamp(x, 0.0, float(size));
    y = clamp(y, 0.0, float(size));
    int i0 = int(floor(x - 0.5));
    int j0 = int(floor(y - 0.5));
    f = vec2(x - (float(i0) + 0.5), y - (float(j0) + 0.5));
    return ivec2(i0, j0);
}

// The same footprint of `face` in a bordered level of face size `size`: its first texel's index
// within the level (pyramidTexelIndex). Shared with pyramid_tail.comp's reads of the levels it keeps
// in shared memory.
uint bilinearFootprint(int size, int face, float x, float y, out vec2 f) {
    ivec2 first = footprintFirst(size, x, y, f);
    return pyramidTexelIndex(face, first.x, first.y, size);
}

// The footprint's texels (first, next in its row, first and next of the next row) weighed by the
// fractions f.
vec3 bilinearBlend(vec2 f, vec3 t00, vec3 t10, vec3 t01, vec3 t11) {
    return ((1.0 - f.x) * (1.0 - f.y)) * t00 + (f.x * (1.0 - f.y)) * t10 + ((1.0 - f.x) * f.y) * t01 + (f.x * f.y) * t11;
}

// Bilinear value of the bordered level of face size `size` whose first texel is `first` in the
// pyramid buffer, at continuous texel coordinates (x, y) of `face`.
vec3 sampleBilinearAt(uint first, int size, int face, float x, float y) {
    vec2 f;
    uint t = first + bilinearFootprint(size, face, x, y, f);
    uint row = uint(size + 2);
    return bilinearBlend(f, pyramidTexel(t), pyramidTexel(t + 1u), pyramidTexel(t + row), pyramidTexel(t + row + 1u));
}

// Bilinear value of pyramid level `level` (face size faceSize >> level) of the invocation's cube at
// continuous texel coordinates (x, y) of `face`.
vec3 sampleBilinear(int faceSize, int level, int face, float x, float y) {
    return sampleBilinearAt(pyramidLevelFirst(faceSize, level), faceSize >> level, face, x, y);
}

// Trilinear value of the levels packed as the pyramid is (levelCount levels from faceSize, the
// invocation's cube of a batch) from texel `first` of the pyramid buffer, at a direction (any length,
// not zero) and a fractional level, clamped to [0, levelCount - 1].
vec3 sampleTrilinearAt(uint first, int faceSize, int levelCount, vec3 direction, float level) {
    level = clamp(level, 0.0, float(levelCount - 1));
    int lower = int(floor(level));
    float upperWeight = level - float(lower);
    int face;
    vec2 uv;
    directionToFaceUv(direction, face, uv);
    vec2 unit = uv + 1.0;
    float half0 = 0.5 * float(faceSize >> lower);
    vec3 value = (1.0 - upperWeight) *
                 sampleBilinearAt(first + pyramidLevelFirst(faceSize, lower), faceSize >> lower, face, unit.x * half0, unit.y * half0);
    if (lower + 1 < levelCount && upperWeight > 0.0) {
        float half1 = 0.5 * float(faceSize >> (lower + 1));
        value += upperWeight * sampleBilinearAt(first + pyramidLevelFirst(faceSize, lower + 1), faceSize >> (lower + 1), face,
                                                unit.x * half1, unit.y * half1);
    }
    return value;
}

// The same for the pyramid itself.
vec3 sampleTrilinear(int faceSize, int levelCount, vec3 direction, float level) {
    return sampleTrilinearAt(0u, faceSize, levelCount, direction, level);
}

#endif
