// The lobes a probe is filtered with, N = V = R: GGX (specular, docs/design.md) and Charlie (sheen,
// KHR_materials_sheen; Estevez & Kulla 2017). The kernel is K(R, l) = D(R.h) max(R.l, 0) for either
// distribution D, so the exact reference, FIS and the measures take the lobe as a parameter.
#pragma once

#include <cmath>
#include <string_view>

#include <glm/vec3.hpp>

#include "probe/ggx.h"

namespace probe {

enum class Lobe { ggx, charlie };
std::string_view lobeName(Lobe lobe);  // "ggx" or "charlie"
Lobe parseLobe(std::string_view name); // ParameterError("method.lobe") for anything else

// The smallest Charlie alpha a level is filtered at: the sheen roughness 0.07 (alpha 0.0049) that
// the glTF sample viewer clamps to. As alpha falls to 0 the Charlie lobe becomes a ring at the
// horizon of R with no weight in front of it, so unlike GGX no level is a copy of the source.
inline constexpr double kCharlieMinAlpha = 0.07 * 0.07;

// The alpha a level of mapping alpha `alpha` is filtered at: alpha for GGX (0: a copy), at least
// kCharlieMinAlpha for Charlie.
inline double lobeAlpha(Lobe lobe, double alpha) { return lobe == Lobe::charlie ? std::fmax(alpha, kCharlieMinAlpha) : alpha; }

// What one output level filters with: the lobe and the alpha it is filtered at (lobeAlpha).
struct LevelLobe {
    Lobe lobe = Lobe::ggx;
    double alpha = 0.0;
};

// Charlie's D(theta_h) = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi) from sin^2(theta_h): with
// N = V = R, sin^2(theta_h) = |R - l|^2 / 4 exactly, which has no cancellation near R = l. It
// integrates to 1 against cos(theta_h) over half vectors, as a microfacet distribution must.
template <typename T>
inline T charlieD(T sinHalf2, T alpha) {
    return (T(2) + T(1) / alpha) * std::pow(sinHalf2, T(0.5) / alpha) / T(2.0 * PROBE_PI);
}

// What a lobe's kernel at alpha > 0 takes besides R.l and |R - l|^2, as the shaders take it
// (shaders/lobe.glsl): GGX's alpha^2; Charlie's exponent 1 / (2 alpha) and the cutoff below.
struct LobeConstants {
    double alpha2 = 0.0;                 // GGX
    double exponent = 0.0, cutoff = 0.0; // Charlie
};
// Below 2^-100 of its largest value Charlie's kernel is 0: a float sum would otherwise add
// denormals (slow on CPUs, flushed on GPUs), and they are far below its rounding.
inline constexpr double kCharlieCutoffLog2 = -100.0;
inline LobeConstants lobeConstants(Lobe lobe, double alpha) {
    if (lobe == Lobe::ggx) return {alpha * alpha, 0.0, 0.0};
    const double exponent = 0.5 / alpha;
    return {0.0, exponent, std::exp2(kCharlieCutoffLog2 / exponent)};
}

// Charlie's kernel over D at theta_h = 45 degrees, its largest value in front of R:
// (2 sin^2(theta_h))^exponent max(R.l, 0), so that it is near 1 where it matters at any alpha (D
// itself falls to 2^-100 there at the smallest alpha). Callers normalize, so the factor cancels.
template <typename T>
inline T charlieKernel(T cosRL, T distanceSquared, T exponent, T cutoff) {
    const T x = distanceSquared * T(0.5);
    return cosRL > T(0) && x > cutoff ? std::pow(x, exponent) * cosRL : T(0);
}

// Calls visit(kernel) with the lobe's kernel K(R, l) at alpha > 0, not normalized, as a callable
// kernel(R.l, |R - l|^2) in T for unit R and l: a type per lobe, so that the inner loops it runs in
// carry no branch on the lobe.
template <typename T, typename Visit>
decltype(auto) visitLobeKernel(Lobe lobe, double alpha, Visit&& visit) {
    const LobeConstants c = lobeConstants(lobe, alpha);
    if (lobe == Lobe::ggx) {
        const T alpha2 = T(c.alpha2);
        return visit([alpha2](T cosRL, T distanceSquared) { return ggxKernel(cosRL, distanceSquared, alpha2); });
    }
    const T exponent = T(c.exponent), cutoff = T(c.cutoff);
    return visit([exponent, cutoff](T cosRL, T distanceSquared) { return charlieKernel(cosRL, distanceSquared, exponent, cutoff); });
}

// A half vector of the lobe for the uniform point (e1, e2) in [0, 1)^2, in the tangent frame of the
// normal (normal = +z), and the density over reflected directions l = reflect(-n, h) of the samples
// it makes, with v = n. GGX: ggxHalfVector, density D / 4. Charlie: density D cos(theta_h) over
// half vectors, restricted to theta_h < 45 degrees, the only half vectors whose l is in front of n
// (without the restriction a low-roughness lobe sends almost every sample behind it): sin(theta_h)
// = (P e1)^(alpha / (2 alpha + 1)) with P = 2^-(1 + 1 / (2 alpha)), the probability of the
// restricted range, and density D / (4 P).
struct LobeSample {
    glm::dvec3 halfVector;
    double pdf = 0.0; // of l = 2 (n.h) h - n, per steradian
};
LobeSample lobeSample(Lobe lobe, double e1, double e2, double alpha);

} // namespace probe
