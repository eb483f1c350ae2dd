// Order-2 SH irradiance: the basis, the white furnace, and agreement with the exact cosine
// convolution on band-limited radiance; the Lambertian irradiance cube and SH measured against it.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "probe/irradiance.h"
#include "probe/reference.h"
#include "probe/sh.h"
#include "probe/synthetic.h"

using namespace probe;

namespace {

// L = 1 + 0.5 z + 0.3 x y, in the span of bands 0..2: order-2 SH irradiance is exact for it up to
// quadrature.
CubeImage bandLimitedRadiance(int size) {
    CubeImage radiance(size);
    const CubeGeometry g(size);
    for (std::size_t t = 0; t < texelCount(size); ++t) {
        const glm::dvec3& d = g.directions[t];
        radiance.set(t, glm::vec3(float(1.0 + 0.5 * d.z + 0.3 * d.x * d.y)));
    }
    return radiance;
}

} // namespace

TEST(Sh, BasisIsOrthonormalUnderCubeQuadrature) {
    const int size = 64;
    const CubeGeometry g(size);
    for (int a = 0; a < kShCount; ++a)
        for (int b = 0; b < kShCount; ++b) {
            double dot = 0.0;
            for (std::size_t t = 0; t < texelCount(size); ++t)
                dot += shBasis(g.directions[t])[a] * shBasis(g.directions[t])[b] * g.solidAngles[t];
            // Texel-centre quadrature of the quadratic band at 64^2 is good to ~1e-4.
            EXPECT_NEAR(dot, a == b ? 1.0 : 0.0, 2e-4) << a << "," << b;
        }
}

TEST(Sh, WhiteFurnace) {
    const ShCoefficients e = radianceToIrradiance(projectRadiance(constantProbe(32, glm::vec3(3.0f))));
    const CubeImage out = shToCube(e, 4);
    for (float v : out.rgb) EXPECT_NEAR(v, 3.0f, 3e-5f);
}

TEST(Sh, MatchesTheExactCosineConvolutionForBandLimitedRadiance) {
    const CubeImage radiance = bandLimitedRadiance(64);
    const CubeImage sh = shToCube(radianceToIrradiance(projectRadiance(radiance)), 8);
    const CubeImage exact = exactIrradiance(radiance, 8);
    for (std::size_t k = 0; k < sh.rgb.size(); ++k) EXPECT_NEAR(sh.rgb[k], exact.rgb[k], 2e-4);
}

// One bright texel: the order-2 truncation rings below zero on the far side (1560 of the 4608
// values of a 16^2 strip), and shToCube clamps it to 0 there and keeps it elsewhere.
TEST(Sh, IrradianceIsClampedToZeroWhereTheTruncationRings) {
    const ShCoefficients e = radianceToIrradiance(projectRadiance(impulseProbe(16, {0, 7, 7}, 100.0f)));
    const CubeImage clamped = shToCube(e, 16);
    const CubeGeometry geometry(16);
    std::size_t negative = 0;
    for (std::size_t t = 0; t < texelCount(16); ++t) {
        const glm::dvec3 value = evaluateSh(e, geometry.directions[t]);
        for (int c = 0; c < 3; ++c) {
            const float expected = static_cast<float>(std::max(value[c], 0.0));
            negative += value[c] < 0.0;
            EXPECT_EQ(clamped.rgb[3 * t + c], expected);
        }
    }
    RecordProperty("negative values", std::to_string(negative));
    EXPECT_GT(negative, texelCount(16)); // a third of the values: the clamp matters
}

// The irradiance cube of a source above kIrradianceSourceSize, computed from its box-averaged
// 128^2 level, is within 1e-3 of the exact convolution of the whole source; on band-limited
// radiance SH equals it (irradianceDifference near 0), on a sun it does not.
TEST(Irradiance, CubeFromTheAveragedSourceEqualsTheFullConvolution) {
    const CubeImage source = sunSkyProbe(256);
    const CubeImage cube = irradianceCube(source);
    ASSERT_EQ(cube.size, kIrradianceCubeSize);
    const IrradianceDifference d = irradianceDifference(cube, exactIrradiance(source, kIrradianceCubeSize));
    RecordProperty("relative L1 of the averaged source", fmt::format("{:.3g}", d.relativeL1));
    EXPECT_LT(d.relativeL1, 1e-3);
    EXPECT_LT(d.maxRelative, 1e-2);
}

TEST(Irradiance, ShAgainstTheCube) {
    const CubeImage smooth = bandLimitedRadiance(32);
    const auto shCube = [](const CubeImage& radiance) {
        return shToCube(radianceToIrradiance(projectRadiance(radiance)), kIrradianceCubeSize);
    };
    EXPECT_LT(irradianceDifference(shCube(smooth), irradianceCube(smooth)).relativeL1, 1e-4);
    const CubeImage sun = sunSkyProbe(32);
    const IrradianceDifference d = irradianceDifference(shCube(sun), irradianceCube(sun));
    EXPECT_GT(d.relativeL1, 1e-3); // order 2 cannot hold a sun's sharp cosine edge
    EXPECT_EQ(irradianceDifference(irradianceCube(sun), irradianceCube(sun)).relativeL1, 0.0);
}
