// The GGX lobe of DESIGN.md in a form that stays accurate in float32 for tiny alpha.
#pragma once

#include <numbers>

namespace probe {

// D(c) = alpha^2 / (pi (c^2 (alpha^2 - 1) + 1)^2) evaluated through the identity
// c^2 (alpha^2 - 1) + 1 = |R - l|^2 / 4 + c^2 alpha^2 with c^2 = (1 + R.l) / 2, which has no
// cancellation near R = l. Inputs: R.l, |R - l|^2 and alpha^2 (alpha = perceptual roughness^2).
template <typename T>
inline T ggxD(T cosRL, T distanceSquared, T alpha2) {
    const T cosHalf2 = (T(1) + cosRL) * T(0.5);
    const T q = distanceSquared * T(0.25) + cosHalf2 * alpha2;
    return alpha2 / (std::numbers::pi_v<T> * q * q);
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

} // namespace probe
