// Pass 1: one level of the pyramid from the next finer one, mirroring core/src/pyramid.cpp.
// bspline: four seamless bilinear taps at +-0.75 fine texels around the coarse texel centre, tap k
// weighing 0.5 J_k / sum(J) + 0.125 with J = (1 + u^2 + v^2)^(-3/2) at the tap (or its inverse).
// box: the 2x2 children on the same face, each weighing its exact solid angle (or its inverse),
// normalized.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "probe/shared_constants.h"
#include "sampling.glsl"

layout(local_size_x = 64) in;

layout(push_constant) uniform Params {
    int baseSize;         // S_0
    int fineLevel;        // writes level fineLevel + 1
    int boxKind;          // 0: bspline, 1: box
    int inverseSolidAngle; // 0: weigh by the solid angle, 1: by its inverse
} params;

float jacobianWeight(float u, float v) {
    float density = pow(1.0 + u * u + v * v, -1.5);
    return params.inverseSolidAngle == 0 ? density : 1.0 / density;
}

vec3 bspline(ivec3 coarse, int fineSize) {
    vec3 value[4];
    float j[4];
    float jSum = 0.0;
    for (int k = 0; k < 4; ++k) {
        float x = 2.0 * float(coarse.y) + 1.0 + ((k & 1) != 0 ? PROBE_PYRAMID_TAP_OFFSET : -PROBE_PYRAMID_TAP_OFFSET);
        float y = 2.0 * float(coarse.z) + 1.0 + ((k >> 1) != 0 ? PROBE_PYRAMID_TAP_OFFSET : -PROBE_PYRAMID_TAP_OFFSET);
        value[k] = sampleBilinear(params.baseSize, params.fineLevel, coarse.x, x, y);
        j[k] = jacobianWeight(2.0 * x / float(fineSize) - 1.0, 2.0 * y / float(fineSize) - 1.0);
        jSum += j[k];
    }
    vec3 sum = vec3(0.0);
    for (int k = 0; k < 4; ++k) sum += (PROBE_PYRAMID_JACOBIAN_SHARE * j[k] / jSum + PROBE_PYRAMID_BASE_WEIGHT) * value[k];
    return sum;
}

vec3 box(ivec3 coarse, int fineSize) {
    uint first = levelOffset(params.baseSize, params.fineLevel);
    vec3 sum = vec3(0.0);
    float weightSum = 0.0;
    for (int k = 0; k < 4; ++k) {
        uint child = first + texelIndex(coarse.x, 2 * coarse.y + (k & 1), 2 * coarse.z + (k >> 1), fineSize);
        float area = geometry[child].w;
        float w = params.inverseSolidAngle == 0 ? area : 1.0 / area;
        sum += w * pyramid[child].rgb;
        weightSum += w;
    }
    return sum / weightSum;
}

void main() {
    int coarseSize = params.baseSize >> (params.fineLevel + 1);
    uint texel = invocationIndex();
    if (texel >= 6u * uint(coarseSize * coarseSize)) return;
    ivec3 coarse = texelOfIndex(texel, coarseSize);
    vec3 value = params.boxKind == 0 ? bspline(coarse, 2 * coarseSize) : box(coarse, 2 * coarseSize);
    pyramid[levelOffset(params.baseSize, params.fineLevel + 1) + texel] = vec4(value, 1.0);
}
