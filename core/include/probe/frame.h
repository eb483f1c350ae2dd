// The per-tap math of Pass 2, exactly as docs/design.md "Frames" and "Polynomial domain" say: the three
// frames of an output texel, their weights, the polynomial domain (theta, phi), and the evaluation
// of one tap from its table coefficients. The GLSL shader mirrors this file line by line; the
// constants come from shared_constants.h. Tap evaluation is templated on the scalar type so that
// the optimizer's autodiff types flow through it.
#pragma once

#include <array>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "probe/cube_footprint.h"
#include "probe/shared_constants.h"

namespace probe {

inline constexpr int kFrameCount = 3;
// The 5 parameters of a tap: direction in the frame basis (x, y, z), pyramid level, weight.
inline constexpr int kTapParameterCount = 5;
enum TapParameter : int { tapDirX = 0, tapDirY = 1, tapDirZ = 2, tapLevel = 3, tapWeight = 4 };

// The two other axes of frame `axis`, in increasing order.
inline std::array<int, 2> frameOtherAxes(int axis) { return {axis == 0 ? 1 : 0, axis == 2 ? 1 : 2}; }

// Everything about one frame at one output texel that does not depend on the table.
struct FrameSetup {
    double weight = 0.0;               // (max(|d_b|, |d_c|) - 0.75) / 0.25; the frame is skipped where <= 0
    glm::dvec3 x{0.0}, y{0.0}, z{0.0}; // z = R, x = normalize(axis x R), y = R x x
    double theta2 = 0.0, phi2 = 0.0;   // the polynomial domain, squared
};

// The weight of frame `axis` at cube vector d: (max(|d_b|, |d_c|) - 0.75) / 0.25.
inline double frameWeight(const glm::dvec3& d, int axis) {
    const auto [b, c] = frameOtherAxes(axis);
    return (std::max(std::abs(d[b]), std::abs(d[c])) - PROBE_FRAME_BAND_START) / PROBE_FRAME_BAND_WIDTH;
}

// The frame `axis` of the output texel with cube vector d (major component exactly 1 in magnitude,
// as faceUvToCubePoint gives it).
inline FrameSetup frameSetup(const glm::dvec3& d, int axis) {
    const auto [b, c] = frameOtherAxes(axis);
    FrameSetup f;
    f.weight = frameWeight(d, axis);
    if (f.weight <= 0.0) return f;

    glm::dvec3 up(0.0);
    up[axis] = 1.0;
    f.z = glm::normalize(d);
    f.x = glm::normalize(glm::cross(up, f.z));
    f.y = glm::cross(f.z, f.x);

    // theta walks the boundary of the square [-1, 1]^2 that (x', y') lies on.
    const double z = std::abs(d[axis]);
    const double m = std::max(std::abs(d[b]), std::abs(d[c]));
    const double xs = d[b] / m, ys = d[c] / m;
    double theta;
    if (ys < xs) theta = ys <= -PROBE_THETA_EDGE ? xs : ys;
    else theta = ys >= PROBE_THETA_EDGE ? -xs : -ys;
    const double phi = z >= 1.0 - PROBE_POLE_EPSILON ? m : z;
    f.theta2 = theta * theta;
    f.phi2 = phi * phi;
    return f;
}

// A tap as the pyramid sees it: a direction scaled so its major component is 1, an absolute
// pyramid level (before the sampler's clamp) and a weight (frame weight included).
template <typename T>
struct TapSample {
    std::array<T, 3> direction;
    T level;
    T weight;
};

// P = c0 + c1 theta^2 + c2 phi^2 (coefficientCount 3) or P = c0 (coefficientCount 1).
template <typename T>
inline T tapPolynomial(const T* c, int coefficientCount, const FrameSetup& f) {
    return coefficientCount == 1 ? c[0] : c[0] + c[1] * T(f.theta2) + c[2] * T(f.phi2);
}

// One tap from its coefficients (kTapParameterCount * coefficientCount values, parameter-major).
template <typename T>
TapSample<T> evaluateTap(const FrameSetup& f, const T* coefficients, int coefficientCount) {
    using std::abs;
    using std::log2;
    std::array<T, kTapParameterCount> p;
    for (int k = 0; k < kTapParameterCount; ++k) p[k] = tapPolynomial(coefficients + k * coefficientCount, coefficientCount, f);

    TapSample<T> s;
    for (int k = 0; k < 3; ++k) s.direction[k] = T(f.x[k]) * p[tapDirX] + T(f.y[k]) * p[tapDirY] + T(f.z[k]) * p[tapDirZ];
    int major = 0;
    for (int k = 1; k < 3; ++k)
        if (std::abs(scalarValue(s.direction[k])) > std::abs(scalarValue(s.direction[major]))) major = k;
    const T scale = abs(s.direction[major]);
    for (T& v : s.direction) v = v / scale;
    const T length2 = s.direction[0] * s.direction[0] + s.direction[1] * s.direction[1] + s.direction[2] * s.direction[2];
    s.level = p[tapLevel] + T(PROBE_LEVEL_JACOBIAN_SCALE) * log2(length2);
    s.weight = p[tapWeight] * T(f.weight);
    return s;
}

} // namespace probe
