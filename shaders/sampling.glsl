// Seamless bilinear and trilinear reads of the pyramid buffer, mirroring core's
// probe/cube_sampling.h with the shader's own arithmetic: texel coordinates x = (u + 1) / 2 * S
// clamped to [0, S], a footprint texel beyond one face edge read from the adjacent face
// (probe::texelNeighbour), and at a cube corner, where one footprint texel does not exist, the Vulkan
// rule: the missing texel is the average of the other three, so its weight goes 1/3 to each.
#ifndef PROBE_SAMPLING_GLSL
#define PROBE_SAMPLING_GLSL

#include "buffers.glsl"
#include "cube.glsl"

// Texel (i, j) of `face` in a level of `size` where exactly one of i, j is one step outside the
// face: the texel centre beyond the edge, on the face's extended plane, projected onto the
// adjacent face.
ivec3 texelAcrossEdge(int face, int i, int j, int size) {
    return directionToTexel(faceUvToCubePoint(face, texelCentreUv(i, size), texelCentreUv(j, size)), size);
}

// Bilinear value of pyramid level `level` (face size baseSize >> level) at continuous texel
// coordinates (x, y) of `face`.
vec3 sampleBilinear(int baseSize, int level, int face, float x, float y) {
    int size = baseSize >> level;
    uint first = levelOffset(baseSize, level);
    x = clamp(x, 0.0, float(size));
    y = clamp(y, 0.0, float(size));
    int i0 = int(floor(x - 0.5));
    int j0 = int(floor(y - 0.5));
    float fx = x - (float(i0) + 0.5), fy = y - (float(j0) + 0.5);
    float w[4] = float[4]((1.0 - fx) * (1.0 - fy), fx * (1.0 - fy), (1.0 - fx) * fy, fx * fy);
    vec3 value[4];
    int missing = -1;
    for (int k = 0; k < 4; ++k) {
        int i = i0 + (k & 1), j = j0 + (k >> 1);
        bool insideI = i >= 0 && i < size, insideJ = j >= 0 && j < size;
        value[k] = vec3(0.0);
        if (insideI && insideJ) {
            value[k] = pyramid[first + texelIndex(face, i, j, size)].rgb;
        } else if (insideI || insideJ) {
            ivec3 t = texelAcrossEdge(face, i, j, size);
            value[k] = pyramid[first + texelIndex(t.x, t.y, t.z, size)].rgb;
        } else {
            missing = k;
        }
    }
    float share = missing >= 0 ? w[missing] * (1.0 / 3.0) : 0.0;
    vec3 sum = vec3(0.0);
    for (int k = 0; k < 4; ++k)
        if (k != missing) sum += (w[k] + share) * value[k];
    return sum;
}

// Trilinear value of the pyramid (levelCount levels from baseSize) at a direction (any length, not
// zero) and a fractional level, clamped to [0, levelCount - 1].
vec3 sampleTrilinear(int baseSize, int levelCount, vec3 direction, float level) {
    level = clamp(level, 0.0, float(levelCount - 1));
    int lower = int(floor(level));
    float upperWeight = level - float(lower);
    int face;
    vec2 uv;
    directionToFaceUv(direction, face, uv);
    vec2 unit = uv + 1.0;
    float half0 = 0.5 * float(baseSize >> lower);
    vec3 value = (1.0 - upperWeight) * sampleBilinear(baseSize, lower, face, unit.x * half0, unit.y * half0);
    if (lower + 1 < levelCount && upperWeight > 0.0) {
        float half1 = 0.5 * float(baseSize >> (lower + 1));
        value += upperWeight * sampleBilinear(baseSize, lower + 1, face, unit.x * half1, unit.y * half1);
    }
    return value;
}

#endif
