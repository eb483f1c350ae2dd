// The exact reference: white furnace, impulse responses against the lobe, the lobe's peak and width,
// rotational symmetry and the mirror level.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <gtest/gtest.h>

#include "probe/ggx.h"
#include "probe/reference.h"
#include "probe/synthetic.h"

using namespace probe;

namespace {

// The lobe evaluated independently of the library's stable form, in double.
double textbookKernel(const glm::dvec3& R, const glm::dvec3& l, double alpha) {
    const double cosRL = glm::dot(R, l);
    if (cosRL <= 0.0) return 0.0;
    const glm::dvec3 h = glm::normalize(R + l);
    const double c = glm::dot(R, h), a2 = alpha * alpha;
    return a2 / (std::numbers::pi * std::pow(c * c * (a2 - 1.0) + 1.0, 2)) * cosRL;
}

double relativeDifference(const CubeImage& a, const CubeImage& b) {
    double worst = 0.0, scale = 0.0;
    for (std::size_t k = 0; k < a.rgb.size(); ++k) {
        worst = std::max(worst, double(std::abs(a.rgb[k] - b.rgb[k])));
        scale = std::max(scale, double(std::abs(b.rgb[k])));
    }
    return worst / scale;
}

// 90 degree rotation of a cube image: texel centres map onto texel centres exactly.
CubeImage rotate(const CubeImage& in, const glm::dmat3& rotation) {
    CubeImage out(in.size);
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < in.size; ++j)
            for (int i = 0; i < in.size; ++i) {
                const Texel t{f, i, j};
                const Texel to = directionToTexel(rotation * texelDirection(t, in.size), in.size);
                out.set(texelIndex(to, in.size), in.texel(texelIndex(t, in.size)));
            }
    return out;
}

} // namespace

TEST(Reference, WhiteFurnaceEveryMapping) {
    const glm::vec3 radiance(0.25f, 1.0f, 3.0f);
    const CubeImage constant = constantProbe(16, radiance);
    for (const std::string& name : roughnessMappingNames())
        for (int levels : {defaultLevelCount(16), maxLevelCount(16)}) {
            const CubeLevels out = referenceFilter(constant, levels, parseRoughnessMapping(name));
            ASSERT_EQ(out.size(), std::size_t(levels));
            for (int m = 0; m < levels; ++m) {
                ASSERT_EQ(out[m].size, 16 >> m);
                for (std::size_t t = 0; t < texelCount(out[m].size); ++t)
                    for (int c = 0; c < 3; ++c) ASSERT_NEAR(out[m].texel(t)[c], radiance[c], 1e-5 * radiance[c]) << name << " level " << m;
            }
        }
}

TEST(Reference, ImpulseResponseIsTheNormalizedLobe) {
    // Impulses at a face centre, an edge and a corner texel of the source; by linearity the output
    // at every R is that texel's normalized kernel weight.
    const int source = 16, outSize = 8;
    const CubeGeometry geometry(source);
    const Texel impulses[] = {{4, 8, 8}, {4, 15, 7}, {4, 0, 0}};
    for (double alpha : {0.05, 0.25, 1.0})
        for (const Texel& impulse : impulses) {
            const CubeImage response = referenceLevel(impulseProbe(source, impulse), outSize, alpha);
            const CubeGeometry outGeometry(outSize);
            double peak = 0.0;
            std::vector<double> expected(texelCount(outSize));
            for (std::size_t o = 0; o < expected.size(); ++o) {
                const glm::dvec3& R = outGeometry.directions[o];
                double sum = 0.0;
                for (std::size_t t = 0; t < texelCount(source); ++t)
                    sum += textbookKernel(R, geometry.directions[t], alpha) * geometry.solidAngles[t];
                const std::size_t k = texelIndex(impulse, source);
                expected[o] = textbookKernel(R, geometry.directions[k], alpha) * geometry.solidAngles[k] / sum;
                peak = std::max(peak, expected[o]);
            }
            for (std::size_t o = 0; o < expected.size(); ++o)
                ASSERT_NEAR(response.texel(o).r, expected[o], 1e-6 * peak) << "alpha " << alpha << " texel " << o;
        }
}

TEST(Reference, KernelMatchesLobeAtCentreEdgeAndCorner) {
    const int size = 16;
    const CubeGeometry geometry(size);
    for (double alpha : {0.05, 0.25, 1.0})
        for (const Texel& at : {Texel{2, 8, 8}, Texel{2, 15, 7}, Texel{2, 0, 0}}) {
            const glm::dvec3 R = texelDirection(at, size);
            const std::vector<double> k = referenceKernel(R, size, {Lobe::ggx, alpha});
            double sum = 0.0;
            for (std::size_t t = 0; t < k.size(); ++t) sum += textbookKernel(R, geometry.directions[t], alpha) * geometry.solidAngles[t];
            for (std::size_t t = 0; t < k.size(); ++t)
                ASSERT_NEAR(k[t], textbookKernel(R, geometry.directions[t], alpha) * geometry.solidAngles[t] / sum, 1e-12);
        }
}

TEST(Reference, LobeNormalizationIsTheLobesSumAndSymmetric) {
    const int size = 16;
    const CubeGeometry geometry(size);
    for (double alpha : {0.05, 0.25, 1.0})
        for (const Texel& at : {Texel{2, 8, 8}, Texel{2, 15, 7}, Texel{2, 0, 0}, Texel{5, 3, 11}}) {
            const glm::dvec3 R = texelDirection(at, size);
            const double z = ReferenceLobe(R, geometry, {Lobe::ggx, alpha}).normalization();
            double sum = 0.0;
            for (std::size_t t = 0; t < geometry.directions.size(); ++t)
                sum += textbookKernel(R, geometry.directions[t], alpha) * geometry.solidAngles[t];
            EXPECT_NEAR(z, sum, 1e-12 * sum);
            // Every signed permutation of R's coordinates (a symmetry of the cube) has the same sum.
            const std::array<glm::dvec3, 4> images{glm::dvec3(-R.x, R.y, R.z), glm::dvec3(R.y, R.x, R.z), glm::dvec3(R.z, -R.x, -R.y),
                                                   glm::dvec3(-R.y, R.z, -R.x)};
            for (const glm::dvec3& image : images)
                EXPECT_NEAR(ReferenceLobe(image, geometry, {Lobe::ggx, alpha}).normalization(), z, 1e-12 * z);
        }
}

TEST(Reference, PeakAndHalfMaximumWidthMatchTheAnalyticLobe) {
    // The kernel's density k / dOmega against the continuous lobe K / integral(K).
    const int size = 256;
    const CubeGeometry geometry(size);
    const double pi = std::numbers::pi;
    for (double alpha : {0.05, 0.25, 1.0}) {
        const Texel centre{4, size / 2, size / 2};
        const glm::dvec3 R = texelDirection(centre, size);
        const std::vector<double> k = referenceKernel(R, size, {Lobe::ggx, alpha});

        auto lobe = [&](double theta) {
            const double half = std::sin(theta / 2.0);
            return ggxKernel(std::cos(theta), 4.0 * half * half, alpha * alpha);
        };
        // integral of K over the sphere, fine 1D quadrature in theta.
        double integral = 0.0;
        const int nodes = 200000;
        for (int n = 0; n < nodes; ++n) {
            const double theta = (n + 0.5) / nodes * pi / 2.0;
            integral += 2.0 * pi * lobe(theta) * std::sin(theta) * (pi / 2.0 / nodes);
        }
        const double analyticPeak = lobe(0.0) / integral;
        const double peak = k[texelIndex(centre, size)] / geometry.solidAngles[texelIndex(centre, size)];
        EXPECT_NEAR(peak, analyticPeak, 0.02 * analyticPeak) << "alpha " << alpha;

        // Half-maximum angle: analytic by bisection; measured from the texels' density profile.
        double lo = 0.0, hi = pi / 2.0;
        for (int it = 0; it < 100; ++it) ((lobe(0.5 * (lo + hi)) > 0.5 * lobe(0.0)) ? lo : hi) = 0.5 * (lo + hi);
        const double analyticHalf = 0.5 * (lo + hi);
        double inside = 0.0, outside = pi;
        for (std::size_t t = 0; t < k.size(); ++t) {
            const double theta = std::acos(std::clamp(glm::dot(R, geometry.directions[t]), -1.0, 1.0));
            const double density = k[t] / geometry.solidAngles[t];
            if (density >= 0.5 * peak) inside = std::max(inside, theta);
            else outside = std::min(outside, theta);
        }
        // The profile is monotonic, so the last texel above and the first below bracket the angle.
        EXPECT_LE(inside, outside);
        EXPECT_NEAR(0.5 * (inside + outside), analyticHalf, 0.02 * analyticHalf) << "alpha " << alpha;
    }
}

TEST(Reference, RotatingTheInputRotatesTheOutput) {
    const CubeImage source = roomProbe(8);
    const glm::dmat3 rotations[] = {
        {1, 0, 0, 0, 0, 1, 0, -1, 0}, // 90 degrees about X (column-major)
        {0, 0, -1, 0, 1, 0, 1, 0, 0}, // about Y
        {0, 1, 0, -1, 0, 0, 0, 0, 1}, // about Z
    };
    for (const glm::dmat3& rotation : rotations)
        for (double alpha : {0.1, 0.6}) {
            const CubeImage a = referenceLevel(rotate(source, rotation), 8, alpha);
            const CubeImage b = rotate(referenceLevel(source, 8, alpha), rotation);
            EXPECT_LT(relativeDifference(a, b), 1e-5) << "alpha " << alpha;
        }
}

TEST(Reference, MirrorLevelEqualsTheSource) {
    const CubeImage source = sunSkyProbe(16);
    const CubeLevels out = referenceFilter(source, 4, RoughnessMapping::gltf);
    EXPECT_EQ(out[0].rgb, source.rgb);
}

TEST(Reference, TinyAlphaStaysFiniteAndTendsToACopy) {
    const CubeImage source = sunSkyProbe(16);
    const CubeImage out = referenceLevel(source, 16, 1e-4);
    for (float v : out.rgb) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
    EXPECT_LT(relativeDifference(out, source), 1e-5);
}

TEST(Reference, IrradianceOfAConstantConvergesToTheConstant) {
    // Texel-centre quadrature of the clamped cosine: the hemisphere's rim cuts texels, so the error
    // shrinks with the source size rather than vanishing.
    double previous = 1.0;
    for (int size : {8, 32, 128}) {
        const CubeImage out = exactIrradiance(constantProbe(size, glm::vec3(2.0f)), 4);
        double worst = 0.0;
        for (float v : out.rgb) worst = std::max(worst, std::abs(v - 2.0) / 2.0);
        EXPECT_LT(worst, previous / 4.0) << size;
        previous = worst;
    }
    EXPECT_LT(previous, 1e-5);
}
