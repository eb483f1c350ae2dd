// The error measures of docs/design.md on cases whose answer is known.
#include <gtest/gtest.h>

#include "probe/error_measures.h"
#include "probe/reference.h"
#include "probe/synthetic.h"

using namespace probe;

TEST(ErrorMeasures, ImpulseL1IsZeroForTheSameKernelAndTwoForDisjointOnes) {
    const std::vector<double> k = referenceKernel(texelDirection({0, 3, 4}, 8), 8, {Lobe::ggx, 0.3});
    EXPECT_NEAR(impulseL1(k, k), 0.0, 1e-15);
    // Normalization is part of the measure: a scaled copy has no error.
    std::vector<double> scaled = k;
    for (double& w : scaled) w *= 7.0;
    EXPECT_NEAR(impulseL1(scaled, k), 0.0, 1e-12);
    std::vector<double> a(texelCount(8), 0.0), b(texelCount(8), 0.0);
    a[1] = 1.0;
    b[2] = 1.0;
    EXPECT_DOUBLE_EQ(impulseL1(a, b), 2.0);
}

TEST(ErrorMeasures, AccumulatorWeighsBySolidAngleAndFindsTheWorstTexel) {
    ImpulseErrorAccumulator acc;
    acc.add({0, 0, 0}, 1.0, 0.5);
    acc.add({2, 1, 1}, 3.0, 0.1);
    const ImpulseError e = acc.result();
    EXPECT_DOUBLE_EQ(e.mean, (0.5 + 0.3) / 4.0);
    EXPECT_DOUBLE_EQ(e.max, 0.5);
    EXPECT_EQ(e.worst, (Texel{0, 0, 0}));
}

TEST(ErrorMeasures, ImageL1IsRelativeAndSolidAngleWeighted) {
    const CubeImage ref = constantProbe(4, glm::vec3(2.0f));
    EXPECT_DOUBLE_EQ(imageL1(ref, ref), 0.0);
    EXPECT_NEAR(imageL1(constantProbe(4, glm::vec3(2.2f)), ref), 0.1, 1e-6);
    // One texel off by its whole value: the error is that texel's share of the sphere.
    CubeImage out = ref;
    out.set(texelIndex({1, 0, 0}, 4), glm::vec3(0.0f));
    EXPECT_NEAR(imageL1(out, ref), texelSolidAngle(0, 0, 4) / (4.0 * 3.14159265358979), 1e-6);
}
