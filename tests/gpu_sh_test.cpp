// SH irradiance on the GPU: the coefficients equal probecore's double projection, the irradiance
// they give equals the order-2 truncation of the exact cosine convolution, the white furnace, and
// the same bits on every run.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "gpu_test_support.h"
#include "probe/reference.h"
#include "probe/sh.h"
#include "probe/synthetic.h"

using namespace probe;
using probetest::GpuTest;

namespace {

// Per channel: max over the 9 coefficients of |gpu - cpu|, relative to the largest |cpu|
// coefficient of that channel (the 8 others can be ~0 where the probe is nearly symmetric).
double coefficientError(const ShCoefficients& gpu, const ShCoefficients& cpu) {
    double worst = 0.0;
    for (int channel = 0; channel < 3; ++channel) {
        double largest = 0.0, error = 0.0;
        for (int k = 0; k < kShCount; ++k) {
            largest = std::max(largest, std::abs(cpu[k][channel]));
            error = std::max(error, std::abs(gpu[k][channel] - cpu[k][channel]));
        }
        worst = std::max(worst, error / largest);
    }
    return worst;
}

// max |a - b| over texels and channels, relative to the largest |b|.
double irradianceError(const CubeImage& a, const CubeImage& b) {
    double largest = 0.0, error = 0.0;
    for (std::size_t k = 0; k < b.rgb.size(); ++k) {
        largest = std::max(largest, std::abs(double(b.rgb[k])));
        error = std::max(error, std::abs(double(a.rgb[k]) - b.rgb[k]));
    }
    return error / largest;
}

} // namespace

class GpuSh : public GpuTest {};

TEST_F(GpuSh, CoefficientsEqualTheDoubleProjection) {
    for (int size : {1, 16, 64, 128}) {
        const CubeImage probes[] = {probetest::randomProbe(size, 3), sunSkyProbe(size), roomProbe(size)};
        gpu::ShProjector projector(probetest::testDevice(), size);
        for (const CubeImage& probe : probes) {
            const ShCoefficients gpuCoefficients = projector.project(probe);
            const double error = coefficientError(gpuCoefficients, projectRadiance(probe));
            RecordProperty(fmt::format("size {} relative error", size), fmt::format("{:.3g}", error));
            EXPECT_LT(error, 1e-5) << "face size " << size;
            // The irradiance they give: the order-2 truncation of the exact cosine convolution of
            // this (texel-quadrature) radiance is the CPU's coefficients, convolved.
            const CubeImage gpuIrradiance = shToCube(radianceToIrradiance(gpuCoefficients), 8);
            const CubeImage truncation = shToCube(radianceToIrradiance(projectRadiance(probe)), 8);
            EXPECT_LT(irradianceError(gpuIrradiance, truncation), 1e-5) << "face size " << size;
        }
    }
}

TEST_F(GpuSh, BandLimitedRadianceGivesTheExactIrradiance) {
    // L = 1 + 0.5 z + 0.3 x y lies in bands 0..2: the order-2 truncation is the whole cosine
    // convolution, so SH irradiance equals exactIrradiance up to the texel quadrature.
    const int size = 64;
    CubeImage radiance(size);
    const CubeGeometry g(size);
    for (std::size_t t = 0; t < texelCount(size); ++t) {
        const glm::dvec3& d = g.directions[t];
        radiance.set(
            t, glm::vec3(float(1.0 + 0.5 * d.z + 0.3 * d.x * d.y), float(2.0 - 0.4 * d.x), float(0.5 + 0.2 * (d.x * d.x - d.y * d.y))));
    }
    gpu::ShProjector projector(probetest::testDevice(), size);
    const CubeImage sh = shToCube(radianceToIrradiance(projector.project(radiance)), 8);
    const double error = irradianceError(sh, exactIrradiance(radiance, 8));
    RecordProperty("relative error against exactIrradiance", fmt::format("{:.3g}", error));
    EXPECT_LT(error, 1e-4) << "texel-centre quadrature at 64^2 is good to ~1e-4";
}

TEST_F(GpuSh, WhiteFurnace) {
    gpu::ShProjector projector(probetest::testDevice(), 32);
    const ShCoefficients radiance = projector.project(constantProbe(32, glm::vec3(3.0f)));
    EXPECT_NEAR(radiance[0].r, 3.0 * 4.0 * std::numbers::pi * 0.28209479177387814, 1e-5 * 3.0);
    for (float e : shToCube(radianceToIrradiance(radiance), 4).rgb) EXPECT_NEAR(e, 3.0f, 3e-5f);
}

TEST_F(GpuSh, SameBitsEveryRunAndAFixedSummation) {
    const CubeImage probe = probetest::randomProbe(64, 11);
    gpu::ShProjector projector(probetest::testDevice(), 64);
    const ShCoefficients first = projector.project(probe);
    for (int run = 0; run < 3; ++run) EXPECT_EQ(projector.project(probe), first);
    // 6 * 64^2 = 24576 texels: 24 blocks of 1024, then one.
    ASSERT_EQ(projector.dispatches().size(), 2u);
    EXPECT_EQ(projector.dispatches()[0].groups, 24u);
    EXPECT_EQ(projector.dispatches()[1].groups, 1u);
}

// A probe all at FLT_MAX projects to finite coefficients whose irradiance is FLT_MAX everywhere.
TEST_F(GpuTest, ShOfLargestFiniteValues) {
    constexpr float largest = std::numeric_limits<float>::max();
    gpu::ShProjector projector(probetest::testDevice(), 8);
    const CubeImage irradiance = shToCube(radianceToIrradiance(projector.project(CubeImage(8, glm::vec3(largest)))), 8);
    for (float e : irradiance.rgb) ASSERT_TRUE(std::isfinite(e) && e > 0.999f * largest) << e;
}
