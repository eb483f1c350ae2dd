// The lobes of core/include/probe/lobe.h, K(R, l) = D(R.h) max(R.l, 0). GGX (docs/design.md,
// mirroring core/include/probe/ggx.h): D through c^2 (alpha^2 - 1) + 1 = |R - l|^2 / 4 + c^2 alpha^2,
// c^2 = (1 + R.l) / 2 (no cancellation). Charlie: D from sin^2(theta_h) = |R - l|^2 / 4.
#ifndef PROBE_LOBE_GLSL
#define PROBE_LOBE_GLSL

#include "probe/shared_constants.h"

float ggxD(float cosRL, float distanceSquared, float alpha2) {
    float cosHalf2 = (1.0 + cosRL) * 0.5;
    float q = distanceSquared * 0.25 + cosHalf2 * alpha2;
    return alpha2 / (float(PROBE_PI) * q * q);
}

// K(R, l) = D(R.h) max(R.l, 0), not normalized.
float ggxKernel(float cosRL, float distanceSquared, float alpha2) {
    return cosRL > 0.0 ? ggxD(cosRL, distanceSquared, alpha2) * cosRL : 0.0;
}

// Charlie's kernel over its largest value in front of R, (2 sin^2(theta_h))^exponent max(R.l, 0)
// with exponent 1 / (2 alpha) (probe::charlieKernel): near 1 where it matters at any alpha, where D
// itself falls to 2^-100. Callers normalize.
float charlieKernel(float cosRL, float distanceSquared, float exponent) {
    return cosRL > 0.0 ? pow(distanceSquared * 0.5, exponent) * cosRL : 0.0;
}

#endif
