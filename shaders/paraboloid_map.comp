// Pass 1 of FIS on a dual-paraboloid map (probe::buildParaboloidMap), one map level per dispatch, or
// a window of it where the level exceeds the device's storage-buffer range (FilterPlan::paraboloidWindows):
// level 0 reads the bordered source (pyramid level 0) bilinearly at each texel centre's direction,
// level k averages the 2x2 texels of level k - 1.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "paraboloid.glsl"
#include "footprint.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE) in;

layout(push_constant) uniform Params {
    int faceSize; // S_0
    int level;    // the map level written
    uint start;   // its texels [start, start + count) (front image, then back image)
    uint count;
    uint window; // the pyramid-buffer texel where the window bound at binding 0 starts
} params;

void main() {
    int size = paraboloidSize(params.faceSize) >> params.level;
    if (invocationIndex() >= params.count) return;
    uint index = params.start + invocationIndex();
    int image = int(index) / (size * size), j = int(index) / size % size, i = int(index) % size;
    vec3 value;
    if (params.level == 0) {
        int face;
        vec2 uv;
        directionToFaceUv(paraboloidDirection(image, float(i) + 0.5, float(j) + 0.5, size), face, uv);
        float half0 = 0.5 * float(params.faceSize);
        value = sampleBilinear(params.faceSize, 0, face, (uv.x + 1.0) * half0, (uv.y + 1.0) * half0);
    } else {
        int fine = 2 * size;
        uint f = paraboloidLevelOffset(params.faceSize, params.level - 1) + uint(image * fine * fine + 2 * j * fine + 2 * i);
        value = 0.25 * (pyramidTexel(f) + pyramidTexel(f + 1u) + pyramidTexel(f + uint(fine)) + pyramidTexel(f + uint(fine) + 1u));
    }
    storePyramid(paraboloidLevelOffset(params.faceSize, params.level) + index, params.window, value);
}
