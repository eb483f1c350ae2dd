// The GGX lobe of docs/design.md, mirroring core/include/probe/ggx.h: D through
// c^2 (alpha^2 - 1) + 1 = |R - l|^2 / 4 + c^2 alpha^2, c^2 = (1 + R.l) / 2 (no cancellation).
#ifndef PROBE_GGX_GLSL
#define PROBE_GGX_GLSL

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

#endif
