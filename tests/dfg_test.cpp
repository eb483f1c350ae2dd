// The split-sum DFG table: its known limits, its range, and agreement with a brute-force quadrature
// of the same integral over the hemisphere (which shares no code with the importance sampling).
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "probe/dfg.h"

using namespace probe;

namespace {

// (A, B) by the midpoint rule over (theta, phi) of the light direction, textbook D and Filament's V.
glm::dvec2 bruteForceDfg(double nDotV, double roughness, int steps) {
    const double pi = std::numbers::pi, a2 = std::pow(roughness, 4.0);
    const double vx = std::sqrt(1.0 - nDotV * nDotV), vz = nDotV;
    glm::dvec2 sum(0.0);
    for (int i = 0; i < steps; ++i)
        for (int k = 0; k < 2 * steps; ++k) {
            const double theta = (i + 0.5) / steps * pi / 2.0, phi = (k + 0.5) / (2 * steps) * 2.0 * pi;
            const double lx = std::sin(theta) * std::cos(phi), ly = std::sin(theta) * std::sin(phi), lz = std::cos(theta);
            double hx = lx + vx, hy = ly, hz = lz + vz;
            const double norm = std::sqrt(hx * hx + hy * hy + hz * hz);
            hx /= norm, hy /= norm, hz /= norm;
            const double d = a2 / (pi * std::pow(hz * hz * (a2 - 1.0) + 1.0, 2.0));
            const double v = 0.5 / (vz * std::sqrt(lz * lz * (1.0 - a2) + a2) + lz * std::sqrt(vz * vz * (1.0 - a2) + a2));
            const double fresnel = std::pow(1.0 - (vx * hx + vz * hz), 5.0);
            const double w = d * v * lz * std::sin(theta) * (pi / 2.0 / steps) * (pi / steps);
            sum += glm::dvec2((1.0 - fresnel) * w, fresnel * w);
        }
    return sum;
}

} // namespace

TEST(Dfg, SmoothSurfaceAtNormalIncidenceReflectsEverything) {
    const glm::dvec2 mirror = dfgIntegral(1.0, 0.0, 64);
    EXPECT_NEAR(mirror.x + mirror.y, 1.0, 1e-12);
    EXPECT_NEAR(mirror.y, 0.0, 1e-12) << "Schlick's term vanishes at v.h = 1";
    double previous = 1.0;
    for (double roughness : {0.02, 0.05, 0.1, 0.2}) {
        const glm::dvec2 ab = dfgIntegral(1.0, roughness, 1024);
        EXPECT_NEAR(ab.x + ab.y, 1.0, 2.0 * roughness * roughness) << roughness;
        EXPECT_LE(ab.x + ab.y, previous + 1e-9) << "albedo falls with roughness";
        previous = ab.x + ab.y;
    }
}

TEST(Dfg, TableValuesLieInTheUnitInterval) {
    const Image table = dfgTable(32, 256);
    ASSERT_EQ(table.width, 32);
    for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 32; ++i) {
            const glm::vec3 p = table.pixel(i, j);
            EXPECT_GE(p.r, 0.0f);
            EXPECT_GE(p.g, 0.0f);
            // The albedo A + B is at most 1 (so are A and B); 256 samples resolve it to ~2e-4 near
            // the mirror, where single samples weigh more than 1.
            EXPECT_LE(p.r + p.g, 1.0f + 5e-4f) << i << "," << j;
            EXPECT_EQ(p.b, 0.0f);
        }
    // Texel centres: column 0 is n.v = 1/64, row 31 roughness 63/64.
    const glm::dvec2 corner = dfgIntegral(1.0 / 64.0, 63.0 / 64.0, 256);
    EXPECT_FLOAT_EQ(table.pixel(0, 31).r, float(corner.x));
    EXPECT_FLOAT_EQ(table.pixel(0, 31).g, float(corner.y));
}

TEST(Dfg, EqualsBruteForceQuadrature) {
    for (double roughness : {0.5, 0.75, 1.0})
        for (double nDotV : {0.2, 0.5, 0.9}) {
            const glm::dvec2 sampled = dfgIntegral(nDotV, roughness, 16384);
            const glm::dvec2 exact = bruteForceDfg(nDotV, roughness, 600);
            EXPECT_NEAR(sampled.x, exact.x, 1e-3) << "A at roughness " << roughness << ", n.v " << nDotV;
            EXPECT_NEAR(sampled.y, exact.y, 1e-3) << "B at roughness " << roughness << ", n.v " << nDotV;
        }
}
