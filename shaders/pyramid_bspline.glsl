// The B-spline step of pass 1, mirroring core/src/pyramid.cpp: a coarse texel from four bilinear
// taps of the finer level at +-PROBE_PYRAMID_TAP_OFFSET fine texels around its centre, tap k weighing
// PROBE_PYRAMID_JACOBIAN_SHARE J_k / sum(J) + PROBE_PYRAMID_BASE_WEIGHT with J = (1 + u^2 + v^2)^(-3/2)
// at the tap (or its inverse). Shared by pyramid.comp, pyramid_image.comp, pyramid_tail.comp and the
// engine drop-in engine/probe_pyramid.glsl; the includer defines first:
//   vec3 probeSampleFine(int face, float x, float y, int fineSize)  one seamless bilinear read of the
//     finer level (face size fineSize) at fine-texel coordinates (x, y) of `face`
#ifndef PROBE_PYRAMID_BSPLINE_GLSL
#define PROBE_PYRAMID_BSPLINE_GLSL

#include "cube.glsl"
#include "probe/shared_constants.h"

float pyramidJacobianWeight(float u, float v, bool inverseSolidAngle) {
    float r = inversesqrt(1.0 + u * u + v * v);
    float density = r * r * r; // (1 + u^2 + v^2)^(-3/2)
    return inverseSolidAngle ? 1.0 / density : density;
}

// Texel (i, j) of `face` of the coarse level, from the finer level of face size fineSize.
vec3 pyramidBspline(int face, int i, int j, int fineSize, bool inverseSolidAngle) {
    vec3 value[4];
    float weight[4];
    float weightSum = 0.0;
    for (int k = 0; k < 4; ++k) {
        float x = 2.0 * float(i) + 1.0 + ((k & 1) != 0 ? PROBE_PYRAMID_TAP_OFFSET : -PROBE_PYRAMID_TAP_OFFSET);
        float y = 2.0 * float(j) + 1.0 + ((k >> 1) != 0 ? PROBE_PYRAMID_TAP_OFFSET : -PROBE_PYRAMID_TAP_OFFSET);
        value[k] = probeSampleFine(face, x, y, fineSize);
        vec2 uv = texelToFaceUv(x, y, fineSize);
        weight[k] = pyramidJacobianWeight(uv.x, uv.y, inverseSolidAngle);
        weightSum += weight[k];
    }
    vec3 sum = vec3(0.0);
    for (int k = 0; k < 4; ++k) sum += (PROBE_PYRAMID_JACOBIAN_SHARE * weight[k] / weightSum + PROBE_PYRAMID_BASE_WEIGHT) * value[k];
    return sum;
}

#endif
