// The GGX lobe: normalization by quadrature, float32 stability for tiny alpha, and the stable form
// against the textbook one.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "probe/ggx.h"

using namespace probe;

namespace {

// Integrates pdf(l) = D / 4 over the sphere in 1D: the lobe depends only on the angle theta
// between R and l. Substituting theta = 2 atan(alpha tan(phi)) puts the nodes where the lobe is, so
// alpha = 1e-4 is resolved as well as alpha = 1.
template <typename T>
double integratePdf(double alpha, int nodes) {
    const double pi = std::numbers::pi;
    double sum = 0.0;
    for (int k = 0; k < nodes; ++k) {
        const double phi = (k + 0.5) / nodes * pi / 2.0, dPhi = pi / 2.0 / nodes;
        const double t = std::tan(phi);
        const double theta = 2.0 * std::atan(alpha * t);
        const double dTheta = 2.0 * alpha / (std::cos(phi) * std::cos(phi)) / (1.0 + alpha * alpha * t * t);
        const double half = std::sin(theta / 2.0);
        const T pdf = ggxReflectedPdf<T>(T(std::cos(theta)), T(4.0 * half * half), T(alpha * alpha));
        sum += 2.0 * pi * double(pdf) * std::sin(theta) * dTheta * dPhi;
    }
    return sum;
}

} // namespace

TEST(Ggx, PdfIntegratesToOne) {
    for (double alpha : {1e-4, 1e-3, 1e-2, 0.05, 0.1, 0.25, 0.5, 0.75, 1.0}) {
        EXPECT_NEAR(integratePdf<double>(alpha, 20000), 1.0, 1e-6) << "alpha " << alpha;
        EXPECT_NEAR(integratePdf<float>(alpha, 20000), 1.0, 1e-5) << "alpha " << alpha << " in float32";
    }
}

TEST(Ggx, FiniteInFloat32DownToTinyAlpha) {
    for (float alpha : {1e-4f, 3e-4f, 1e-3f, 1e-2f, 0.1f, 1.0f})
        for (int k = 0; k <= 2000; ++k) {
            const double theta = std::numbers::pi * k / 2000.0;
            const float cosRL = float(std::cos(theta)), half = float(std::sin(theta / 2.0));
            const float kernel = ggxKernel(cosRL, 4.0f * half * half, alpha * alpha);
            const float pdf = ggxReflectedPdf(cosRL, 4.0f * half * half, alpha * alpha);
            ASSERT_TRUE(std::isfinite(kernel) && kernel >= 0.0f) << alpha << " " << theta;
            ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0.0f) << alpha << " " << theta;
        }
    // l = R exactly: the peak 1 / (pi alpha^2), finite.
    EXPECT_FLOAT_EQ(ggxD(1.0f, 0.0f, 1e-8f), float(1.0 / (std::numbers::pi * 1e-8)));
}

TEST(Ggx, StableFormEqualsTextbookForm) {
    for (double alpha : {0.05, 0.3, 1.0})
        for (double theta = 0.0; theta < std::numbers::pi; theta += 0.01) {
            const double a2 = alpha * alpha, cosH = std::cos(theta / 2.0);
            const double textbook = a2 / (std::numbers::pi * std::pow(cosH * cosH * (a2 - 1.0) + 1.0, 2));
            const double half = std::sin(theta / 2.0);
            EXPECT_NEAR(ggxD(std::cos(theta), 4.0 * half * half, a2), textbook, 1e-12 * textbook);
        }
}
