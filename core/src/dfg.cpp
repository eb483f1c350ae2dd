#include "probe/dfg.h"

#include <cmath>

#include "probe/ggx.h"
#include "probe/lookup_table.h"

namespace probe {

namespace {

// Filament's height-correlated Smith visibility G / (4 n.l n.v).
double smithVisibility(double nDotV, double nDotL, double alpha2) {
    const double lambdaV = nDotL * std::sqrt(nDotV * nDotV * (1.0 - alpha2) + alpha2);
    const double lambdaL = nDotV * std::sqrt(nDotL * nDotL * (1.0 - alpha2) + alpha2);
    return 0.5 / (lambdaV + lambdaL);
}

} // namespace

glm::dvec2 dfgIntegral(double nDotV, double roughness, int samples) {
    const double alpha = roughness * roughness, alpha2 = alpha * alpha;
    // v in the x-z plane of the normal's tangent frame (normal = +z).
    const glm::dvec3 v(std::sqrt(1.0 - nDotV * nDotV), 0.0, nDotV);
    glm::dvec2 sum(0.0);
    for (int i = 0; i < samples; ++i) {
        const glm::dvec3 h = ggxHalfVector(static_cast<double>(i) / samples, radicalInverse2(static_cast<std::uint32_t>(i)), alpha2);
        const double vDotH = v.x * h.x + v.y * h.y + v.z * h.z;
        const double nDotL = 2.0 * vDotH * h.z - nDotV; // l = 2 (v.h) h - v
        if (nDotL <= 0.0 || vDotH <= 0.0) continue;
        // D V F n.l / pdf(l) with pdf(l) = D n.h / (4 v.h).
        const double weight = smithVisibility(nDotV, nDotL, alpha2) * nDotL * 4.0 * vDotH / h.z;
        const double fresnel = std::pow(1.0 - vDotH, 5.0);
        sum += glm::dvec2((1.0 - fresnel) * weight, fresnel * weight);
    }
    return sum / static_cast<double>(samples);
}

Image dfgTable(int size, int samples) {
    return lookupTable(size, [samples](double nDotV, double roughness) { return dfgIntegral(nDotV, roughness, samples); });
}

} // namespace probe
