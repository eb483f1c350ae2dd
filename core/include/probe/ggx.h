// The GGX lobe of docs/design.md in a form that stays accurate in float32 for tiny alpha.
#pragma once

#include <cmath>
#include <cstdint>

#include <glm/vec3.hpp>

#include "probe/shared_constants.h"

namespace probe {

// D(c) = alpha^2 / (pi (c^2 (alpha^2 - 1) + 1)^2) evaluated through the identity
// c^2 (alpha^2 - 1) + 1 = |R - l|^2 / 4 + c^2 alpha^2 with c^2 = (1 + R.l) / 2, which has no
// cancellation near R = l. Inputs: R.l, |R - l|^2 and alpha^2 (alpha = perceptual roughness^2).
template <typename T>
inline T ggxD(T cosRL, T distanceSquared, T alpha2) {
    const T cosHalf2 = (T(1) + cosRL) * T(0.5);
    const T q = distanceSquared * T(0.25) + cosHalf2 * alpha2;
    return alpha2 / (T(PROBE_PI) * q * q);
}

// The filter kernel K(R, l) = D(R.h) max(R.l, 0) (not normalized), for unit R and l.
template <typename T>
inline T ggxKernel(T cosRL, T distanceSquared, T alpha2) {
    return cosRL > T(0) ? ggxD(cosRL, distanceSquared, alpha2) * cosRL : T(0);
}

// The probability density of the reflected direction l under GGX sampling with v = n = R:
// pdf(l) = D(R.h) / 4; it integrates to 1 over the sphere.
template <typename T>
inline T ggxReflectedPdf(T cosRL, T distanceSquared, T alpha2) {
    return ggxD(cosRL, distanceSquared, alpha2) * T(0.25);
}

// The base-2 radical inverse (van der Corput) of i: the second coordinate of Hammersley point i,
// (i / N, radicalInverse2(i)).
inline double radicalInverse2(std::uint32_t bits) {
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return static_cast<double>(bits) * 0x1p-32;
}

// A GGX-distributed half vector for the uniform point (e1, e2) in [0, 1)^2, in the tangent frame of
// the normal (normal = +z): cos^2(theta) = (1 - e1) / (1 + (alpha^2 - 1) e1), phi = 2 pi e2. Its
// density is D(n.h) (n.h) over half vectors, so the reflected direction has pdf D (n.h) / (4 v.h).
inline glm::dvec3 ggxHalfVector(double e1, double e2, double alpha2) {
    const double cosTheta = std::sqrt((1.0 - e1) / (1.0 + (alpha2 - 1.0) * e1));
    const double sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
    const double phi = 2.0 * PROBE_PI * e2;
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

} // namespace probe
