// The sheen table: its two integrals against a brute-force quadrature over light directions that
// shares no code with it, and the albedo's range.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "probe/sheen.h"

using namespace probe;

namespace {

// (red, green) by the midpoint rule over (theta, phi) of l, h = normalize(v + l), textbook Charlie
// D and the two visibilities written out again.
glm::dvec2 bruteForceSheen(double nDotV, double roughness, int steps) {
    const double pi = std::numbers::pi, alpha = std::max(roughness * roughness, 0.0049);
    const double vx = std::sqrt(1.0 - nDotV * nDotV), vz = nDotV;
    const auto lambda = [alpha](double c) {
        const double t = (1.0 - alpha) * (1.0 - alpha);
        const auto fit = [t](double x) {
            const double a = 21.5473 * (1 - t) + 25.3245 * t, b = 3.82987 * (1 - t) + 3.32435 * t, cc = 0.19823 * (1 - t) + 0.16801 * t;
            const double d = -1.97760 * (1 - t) - 1.27393 * t, e = -4.32054 * (1 - t) - 4.85967 * t;
            return a / (1.0 + b * std::pow(x, cc)) + d * x + e;
        };
        return c < 0.5 ? std::exp(fit(c)) : std::exp(2.0 * fit(0.5) - fit(1.0 - c));
    };
    glm::dvec2 sum(0.0);
    for (int i = 0; i < steps; ++i)
        for (int k = 0; k < 2 * steps; ++k) {
            const double theta = (i + 0.5) / steps * pi / 2.0, phi = (k + 0.5) / (2 * steps) * 2.0 * pi;
            const double lx = std::sin(theta) * std::cos(phi), ly = std::sin(theta) * std::sin(phi), lz = std::cos(theta);
            const double hx = lx + vx, hy = ly, hz = lz + vz, norm = std::sqrt(hx * hx + hy * hy + hz * hz);
            const double cosH = hz / norm, sinH = std::sqrt(std::max(0.0, 1.0 - cosH * cosH));
            const double d = (2.0 + 1.0 / alpha) * std::pow(sinH, 1.0 / alpha) / (2.0 * pi);
            const double neubelt = 1.0 / (4.0 * (lz + vz - lz * vz));
            const double kulla = std::min(1.0, 1.0 / ((1.0 + lambda(vz) + lambda(lz)) * 4.0 * vz * lz));
            const double w = d * lz * std::sin(theta) * (pi / 2.0 / steps) * (pi / steps);
            sum += glm::dvec2(w * neubelt, w * kulla);
        }
    return sum;
}

} // namespace

TEST(Sheen, EqualsBruteForceQuadrature) {
    for (double roughness : {0.3, 0.6, 1.0})
        for (double nDotV : {0.2, 0.5, 0.9}) {
            const glm::dvec2 sampled = sheenIntegral(nDotV, roughness, 1 << 16);
            const glm::dvec2 exact = bruteForceSheen(nDotV, roughness, 800);
            EXPECT_NEAR(sampled.x, exact.x, 2e-3 * std::max(1.0, exact.x)) << "red at roughness " << roughness << ", n.v " << nDotV;
            EXPECT_NEAR(sampled.y, exact.y, 2e-3) << "E at roughness " << roughness << ", n.v " << nDotV;
        }
    // At grazing n.v a smooth sheen's albedo E exceeds 1, and the brute force agrees: the model's.
    const glm::dvec2 grazing = sheenIntegral(1.0 / 32.0, 1.0 / 32.0, 1 << 16), exact = bruteForceSheen(1.0 / 32.0, 1.0 / 32.0, 1500);
    EXPECT_NEAR(grazing.y, exact.y, 2e-3);
    EXPECT_GT(grazing.y, 1.15);
}

TEST(Sheen, AlbedoIsBoundedAwayFromGrazingAndGrowsWithRoughness) {
    // At grazing n.v a smooth sheen's E exceeds 1 (Sheen.EqualsBruteForceQuadrature): the model's,
    // which the visibility's clamp does not bound. From
    // n.v = 0.1 on E is at most 1 and grows with roughness, the lobe reaching further from grazing.
    const int size = 16;
    const Image table = sheenTable(size, 1024);
    for (int i = 0; i < size; ++i) {
        float previous = 0.0f;
        for (int j = 0; j < size; ++j) {
            const glm::vec3 p = table.pixel(i, j);
            EXPECT_GE(p.r, 0.0f);
            EXPECT_GE(p.g, 0.0f);
            EXPECT_LE(p.g, 1.2f) << i << "," << j;
            EXPECT_EQ(p.b, 0.0f);
            if ((i + 0.5) / size < 0.1) continue;
            EXPECT_LE(p.g, 1.0f) << i << "," << j;
            EXPECT_GE(p.g, previous - 1e-3f) << i << "," << j; // 1024 samples resolve it to ~1e-4
            previous = p.g;
        }
    }
}
