#include "probe/lobe.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "probe/error.h"

namespace probe {

std::string_view lobeName(Lobe lobe) { return lobe == Lobe::charlie ? "charlie" : "ggx"; }

Lobe parseLobe(std::string_view name) {
    for (Lobe lobe : {Lobe::ggx, Lobe::charlie})
        if (lobeName(lobe) == name) return lobe;
    throw ParameterError("method.lobe", fmt::format("{}: expected ggx or charlie", name));
}

LobeSample lobeSample(Lobe lobe, double e1, double e2, double alpha) {
    const glm::dvec3 n(0.0, 0.0, 1.0);
    LobeSample s;
    if (lobe == Lobe::ggx) {
        const double alpha2 = alpha * alpha;
        s.halfVector = ggxHalfVector(e1, e2, alpha2);
        const glm::dvec3 l = 2.0 * s.halfVector.z * s.halfVector - n, d = n - l;
        s.pdf = ggxReflectedPdf(l.z, glm::dot(d, d), alpha2);
        return s;
    }
    const double restricted = std::exp2(-(1.0 + 0.5 / alpha));
    const double sinTheta = std::pow(restricted * e1, alpha / (2.0 * alpha + 1.0));
    const double cosTheta = std::sqrt(1.0 - sinTheta * sinTheta);
    const double phi = 2.0 * PROBE_PI * e2;
    s.halfVector = {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
    s.pdf = charlieD(sinTheta * sinTheta, alpha) / (4.0 * restricted);
    return s;
}

} // namespace probe
