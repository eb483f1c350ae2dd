#include "probe/sheen.h"

#include <algorithm>
#include <cmath>

#include "probe/ggx.h"
#include "probe/lobe.h"
#include "probe/lookup_table.h"

namespace probe {

namespace {

// The fit of Lambda's exponent, between its values at alpha 1 and 0 by (1 - alpha)^2.
double lambdaFit(double x, double alpha) {
    const double t = (1.0 - alpha) * (1.0 - alpha);
    const auto mix = [t](double at1, double at0) { return at1 + (at0 - at1) * t; };
    return mix(21.5473, 25.3245) / (1.0 + mix(3.82987, 3.32435) * std::pow(x, mix(0.19823, 0.16801))) + mix(-1.97760, -1.27393) * x +
           mix(-4.32054, -4.85967);
}

double sheenLambda(double cosTheta, double alpha) {
    return cosTheta < 0.5 ? std::exp(lambdaFit(cosTheta, alpha)) : std::exp(2.0 * lambdaFit(0.5, alpha) - lambdaFit(1.0 - cosTheta, alpha));
}

} // namespace

double sheenVisibility(double nDotV, double nDotL, double alpha) {
    const double v = 1.0 / ((1.0 + sheenLambda(nDotV, alpha) + sheenLambda(nDotL, alpha)) * 4.0 * nDotV * nDotL);
    return std::clamp(v, 0.0, 1.0);
}

glm::dvec2 sheenIntegral(double nDotV, double roughness, int samples) {
    const double alpha = lobeAlpha(Lobe::charlie, roughness * roughness);
    const glm::dvec3 v(std::sqrt(1.0 - nDotV * nDotV), 0.0, nDotV);
    glm::dvec2 sum(0.0);
    for (int i = 0; i < samples; ++i) {
        // h uniform over the hemisphere (density 1 / (2 pi)), l = 2 (v.h) h - v, dl = 4 (v.h) dh.
        const double cosTheta = 1.0 - static_cast<double>(i) / samples, sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
        const double phi = 2.0 * PROBE_PI * radicalInverse2(static_cast<std::uint32_t>(i));
        const glm::dvec3 h(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
        const double vDotH = v.x * h.x + v.y * h.y + v.z * h.z;
        const double nDotL = 2.0 * vDotH * h.z - nDotV;
        if (nDotL <= 0.0 || vDotH <= 0.0) continue;
        const double d = charlieD(sinTheta * sinTheta, alpha) * nDotL * 4.0 * vDotH * 2.0 * PROBE_PI;
        const double neubelt = 1.0 / (4.0 * (nDotL + nDotV - nDotL * nDotV));
        sum += glm::dvec2(d * neubelt, d * sheenVisibility(nDotV, nDotL, alpha));
    }
    return sum / static_cast<double>(samples);
}

Image sheenTable(int size, int samples) {
    return lookupTable(size, [samples](double nDotV, double roughness) { return sheenIntegral(nDotV, roughness, samples); });
}

} // namespace probe
