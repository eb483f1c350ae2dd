#include "probe/sh.h"

#include <limits>
#include <numbers>

#include <glm/common.hpp>

#include "probe/shared_constants.h"

namespace probe {

std::array<double, kShCount> shBasis(const glm::dvec3& n) {
    constexpr double c0 = PROBE_SH_C0, c1 = PROBE_SH_C1, c2 = PROBE_SH_C2, c20 = PROBE_SH_C20, c22 = PROBE_SH_C22;
    return {c0,
            c1 * n.y,
            c1 * n.z,
            c1 * n.x,
            c2 * n.x * n.y,
            c2 * n.y * n.z,
            c20 * (3.0 * n.z * n.z - 1.0),
            c2 * n.x * n.z,
            c22 * (n.x * n.x - n.y * n.y)};
}

ShCoefficients projectRadiance(const CubeImage& radiance) {
    const CubeGeometry geometry(radiance.size);
    ShCoefficients c{};
    for (std::size_t t = 0; t < texelCount(radiance.size); ++t) {
        const auto y = shBasis(geometry.directions[t]);
        const glm::dvec3 l = glm::dvec3(radiance.texel(t)) * geometry.solidAngles[t];
        for (int k = 0; k < kShCount; ++k) c[k] += l * y[k];
    }
    return c;
}

ShCoefficients radianceToIrradiance(const ShCoefficients& radiance) {
    constexpr double pi = std::numbers::pi;
    constexpr std::array<double, 3> band{pi, 2.0 * pi / 3.0, pi / 4.0};
    constexpr std::array<int, kShCount> bandOf{0, 1, 1, 1, 2, 2, 2, 2, 2};
    ShCoefficients e{};
    for (int k = 0; k < kShCount; ++k) e[k] = radiance[k] * (band[bandOf[k]] / pi);
    return e;
}

glm::dvec3 evaluateSh(const ShCoefficients& c, const glm::dvec3& n) {
    const auto y = shBasis(n);
    glm::dvec3 sum(0.0);
    for (int k = 0; k < kShCount; ++k) sum += c[k] * y[k];
    return sum;
}

CubeImage shToCube(const ShCoefficients& irradiance, int size) {
    CubeImage out(size);
    const CubeGeometry geometry(size);
    // Order-2 SH rings below zero opposite a bright light; irradiance is not negative. Clamped to
    // FLT_MAX too, as the double sum may exceed it.
    constexpr double largest = std::numeric_limits<float>::max();
    for (std::size_t t = 0; t < texelCount(size); ++t)
        out.set(t, glm::vec3(glm::clamp(evaluateSh(irradiance, geometry.directions[t]), 0.0, largest)));
    return out;
}

} // namespace probe
