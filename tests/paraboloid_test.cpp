// The dual-paraboloid FIS model: the mapping and its Jacobian, a constant probe stays constant
// (white furnace), the impulse response is the filter's linear map, and the kernel lands where
// the exact reference puts it.
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "probe/error_measures.h"
#include "probe/paraboloid.h"
#include "probe/reference.h"

namespace probe {
namespace {

TEST(Paraboloid, MappingRoundTrips) {
    std::mt19937 rng(7);
    std::normal_distribution<double> n;
    for (int k = 0; k < 1000; ++k) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(n(rng), n(rng), n(rng)));
        const ParaboloidPoint p = paraboloidPoint(d, 64);
        EXPECT_EQ(p.image, d.z >= 0.0 ? 0 : 1);
        const glm::dvec3 back = paraboloidDirection(p.image, p.x, p.y, 64);
        EXPECT_NEAR(glm::length(back - d), 0.0, 1e-12);
    }
    // Past the disc, a texel holds a direction of the other hemisphere.
    EXPECT_LT(paraboloidDirection(0, 0.5, 0.5, 64).z, 0.0);
    EXPECT_GT(paraboloidDirection(1, 0.5, 0.5, 64).z, 0.0);
}

TEST(Paraboloid, TexelSolidAnglesOfBothDiscsCoverTheSphere) {
    const int size = 256;
    double total = 0.0;
    for (int image = 0; image < 2; ++image)
        for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i) {
                const glm::dvec3 d = paraboloidDirection(image, i + 0.5, j + 0.5, size);
                if ((d.z >= 0.0) == (image == 0)) total += paraboloidTexelSolidAngle(d, size);
            }
    EXPECT_NEAR(total / (4.0 * std::numbers::pi), 1.0, 5e-3);
}

TEST(Paraboloid, WhiteFurnace) {
    const glm::vec3 white(0.75f, 0.75f, 0.75f);
    const ParaboloidMap map = buildParaboloidMap(CubeImage(16, white));
    ASSERT_EQ(map.levelCount(), 6);
    for (const auto& level : map.levels)
        for (const glm::vec3& texel : level) EXPECT_NEAR(texel.g, 0.75f, 1e-6f);
    FisSettings settings;
    settings.samples = 16;
    const CubeLevels out = paraboloidFilter(CubeImage(16, white), 5, RoughnessMapping::gltf, settings);
    for (const CubeImage& level : out)
        for (float v : level.rgb) EXPECT_NEAR(v, 0.75f, 1e-5f);
}

TEST(Paraboloid, ImpulseResponseIsTheFiltersLinearMap) {
    const int size = 8, levels = 4;
    CubeImage source(size);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> value(0.1f, 2.0f);
    for (float& v : source.rgb) v = value(rng);
    FisSettings settings;
    settings.samples = 24;
    settings.bias = 0.5;
    const CubeLevels out = paraboloidFilter(source, levels, RoughnessMapping::gltf, settings);
    const ParaboloidImpulse impulse(size, levels, RoughnessMapping::gltf, settings);
    for (int m = 1; m < levels; ++m)
        for (const Texel texel : {Texel{0, 0, 0}, Texel{3, (size >> m) - 1, 0}, Texel{5, (size >> m) / 2, (size >> m) / 2}}) {
            const std::vector<double> w = impulse.response(m, texel);
            double red = 0.0, sum = 0.0;
            for (std::size_t t = 0; t < w.size(); ++t) {
                red += w[t] * source.texel(t).r;
                sum += w[t];
            }
            EXPECT_NEAR(sum, 1.0, 1e-9);
            EXPECT_NEAR(red, out[m].texel(texelIndex(texel, size >> m)).r, 1e-5) << "level " << m;
        }
}

TEST(Paraboloid, KernelLandsWhereTheReferencePutsIt) {
    const int size = 16, levels = 5;
    FisSettings settings;
    settings.samples = 256;
    const ParaboloidImpulse impulse(size, levels, RoughnessMapping::gltf, settings);
    for (int m = 1; m < levels; ++m) {
        const Texel texel{2, (size >> m) / 3, (size >> m) / 2};
        const double alpha = levelAlpha(RoughnessMapping::gltf, m, levels);
        const double l1 =
            impulseL1(impulse.response(m, texel), referenceKernel(texelDirection(texel, size >> m), size, {Lobe::ggx, alpha}));
        EXPECT_LT(l1, 0.6) << "level " << m; // a kernel in the wrong place has an L1 near 2
    }
}

} // namespace
} // namespace probe
