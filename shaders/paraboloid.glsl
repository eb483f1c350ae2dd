// The dual-paraboloid map of FIS (probe/paraboloid.h, mirrored line by line): two images per level,
// level k of size (2 S_0) >> k, packed level after level in the pyramid buffer after the bordered
// source (its level 0, which the map's level 0 reads), each level the front image then the back
// image, row-major. Written through windows of binding 0 (paraboloid_map.comp), read through
// pyramidTexel: the whole map can exceed the storage-buffer range a device guarantees.
#ifndef PROBE_PARABOLOID_GLSL
#define PROBE_PARABOLOID_GLSL

#include "buffers.glsl"
#include "probe/shared_constants.h"

int paraboloidSize(int faceSize) { return 2 * faceSize; }
int paraboloidLevelCount(int faceSize) { return findMSB(uint(paraboloidSize(faceSize))) + 1; }

// First texel of map level k in the pyramid buffer: after the bordered source, 2 sum_{l < k} (S >> l)^2
// = 8 (S^2 - (S >> k)^2) / 3.
uint paraboloidLevelOffset(int faceSize, int level) {
    uint s0 = uint(paraboloidSize(faceSize)), s = s0 >> uint(level);
    return pyramidLevelOffset(faceSize, 1) + 8u * (s0 * s0 - s * s) / 3u;
}

// probe::paraboloidDirection
vec3 paraboloidDirection(int image, float x, float y, int size) {
    float u = (2.0 * x / float(size) - 1.0) / float(PROBE_PARABOLOID_SCALE);
    float v = (2.0 * y / float(size) - 1.0) / float(PROBE_PARABOLOID_SCALE);
    float r2 = u * u + v * v;
    float z = (1.0 - r2) / (1.0 + r2);
    return vec3(2.0 * u / (1.0 + r2), 2.0 * v / (1.0 + r2), image == 0 ? z : -z);
}

// probe::paraboloidLevel
float paraboloidLevel(vec3 d, float cubeLevel, int faceSize) {
    d = normalize(d);
    float denominator = 1.0 + abs(d.z);
    float u = d.x / denominator, v = d.y / denominator;
    float texel = 2.0 / (float(PROBE_PARABOLOID_SCALE) * float(paraboloidSize(faceSize)));
    float jacobian = 4.0 / ((1.0 + u * u + v * v) * (1.0 + u * u + v * v));
    float cubeTexel = 4.0 * 3.14159265358979 / (6.0 * float(faceSize) * float(faceSize));
    return cubeLevel + 0.5 * log2(cubeTexel / (jacobian * texel * texel));
}

// Bilinear value of map level k with clamp-to-edge addressing (probe::sampleParaboloid).
vec3 sampleParaboloidLevel(int faceSize, int level, vec3 d) {
    int size = paraboloidSize(faceSize) >> level;
    d = normalize(d);
    int image = d.z >= 0.0 ? 0 : 1;
    float denominator = 1.0 + abs(d.z);
    float half_ = 0.5 * float(size);
    float x = (d.x / denominator * float(PROBE_PARABOLOID_SCALE) + 1.0) * half_;
    float y = (d.y / denominator * float(PROBE_PARABOLOID_SCALE) + 1.0) * half_;
    int i0 = int(floor(x - 0.5)), j0 = int(floor(y - 0.5));
    float fx = x - (float(i0) + 0.5), fy = y - (float(j0) + 0.5);
    uint first = paraboloidLevelOffset(faceSize, level) + uint(image) * uint(size * size);
    int ia = clamp(i0, 0, size - 1), ib = clamp(i0 + 1, 0, size - 1);
    int ja = clamp(j0, 0, size - 1), jb = clamp(j0 + 1, 0, size - 1);
    return ((1.0 - fx) * (1.0 - fy)) * pyramidTexel(first + uint(ja * size + ia)) +
           (fx * (1.0 - fy)) * pyramidTexel(first + uint(ja * size + ib)) + ((1.0 - fx) * fy) * pyramidTexel(first + uint(jb * size + ia)) +
           (fx * fy) * pyramidTexel(first + uint(jb * size + ib));
}

// Trilinear value of the map at a direction and a fractional level, clamped to the chain.
vec3 sampleParaboloid(int faceSize, vec3 d, float level) {
    int levels = paraboloidLevelCount(faceSize);
    level = clamp(level, 0.0, float(levels - 1));
    int lower = int(floor(level));
    float upperWeight = level - float(lower);
    vec3 value = (1.0 - upperWeight) * sampleParaboloidLevel(faceSize, lower, d);
    if (lower + 1 < levels && upperWeight > 0.0) value += upperWeight * sampleParaboloidLevel(faceSize, lower + 1, d);
    return value;
}

#endif
