// The error measures of docs/design.md on cases whose answer is known.
#include <gtest/gtest.h>

#include "probe/error_measures.h"
#include "probe/reference.h"
#include "probe/seam_measure.h"
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

namespace {

// An 8^2 cube of 1s with face +X at `edge`, so that every step across +X's edges is |edge - 1| and
// none inside a face, and one interior texel of -Y at 1 + interior: the steepest interior step.
CubeImage steppedCube(float edge, float interior) {
    const int size = 8;
    CubeImage cube = constantProbe(size, glm::vec3(1.0f));
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) cube.set(texelIndex({0, i, j}, size), glm::vec3(edge));
    cube.set(texelIndex({3, 3, 3}, size), glm::vec3(1.0f + interior));
    return cube;
}

} // namespace

TEST(SeamMeasure, WithinTheBoundByTheRatioOrByTheReferencesEdgeSteps) {
    const CubeImage reference = steppedCube(1.1f, 1.0f);
    EXPECT_NEAR(seamRatio(reference), 0.1, 1e-6);
    const double bound = seamBounds({reference}, 1.0)[0];
    EXPECT_NEAR(bound, 0.11, 1e-6);
    // Smoother inside than the reference, the same seams: its ratio is 5x the reference's, and it is
    // within the bound by its edge steps alone.
    const CubeImage smoother = steppedCube(1.1f, 0.2f);
    EXPECT_GT(seamRatio(smoother), bound);
    EXPECT_TRUE(withinSeamBound(smoother, bound, &reference));
    EXPECT_FALSE(withinSeamBound(smoother, bound, nullptr));
    EXPECT_NEAR(steepestSteps(smoother).edge, steepestSteps(reference).edge, 1e-6);
    // Seams 1.2x the reference's: outside, whatever its interior.
    EXPECT_FALSE(withinSeamBound(steppedCube(1.12f, 0.2f), bound, &reference));
    EXPECT_FALSE(withinSeamBound(steppedCube(1.12f, 1.0f), bound, &reference));
    // The ratio alone still admits a level that steps hard everywhere alike.
    EXPECT_TRUE(withinSeamBound(steppedCube(1.2f, 2.0f), bound, &reference));
}

TEST(SeamMeasure, EdgeStepsAgainstHowHardTheLevelStepsInsideItsFaces) {
    // The sky's exact filter: its steepest step across the quarter lines, and across the edges.
    const int size = 16, levels = 2;
    const CubeLevels reference = skyReference(size, levels, RoughnessMapping::gltf, Lobe::ggx);
    const CubeImage& exact = reference[1];
    const SeamSteps e = steepestSteps(exact);
    ASSERT_GT(e.quarterLine, 0.0);
    ASSERT_GT(e.edge, 0.0);
    // Every step 1.3x the reference's (its contrast about the mean raised): edges and quarter lines
    // alike, within the bound by the edge steps; a step at the edges alone is not.
    const glm::vec3 mean = [&] {
        glm::dvec3 sum(0.0);
        for (std::size_t t = 0; t < texelCount(exact.size); ++t) sum += glm::dvec3(exact.texel(t));
        return glm::vec3(sum / double(texelCount(exact.size)));
    }();
    CubeImage everywhere = exact;
    for (std::size_t t = 0; t < texelCount(exact.size); ++t) everywhere.set(t, mean + 1.3f * (exact.texel(t) - mean));
    EXPECT_NEAR(steepestSteps(everywhere).edge / e.edge, 1.3, 1e-4);
    const double noRatio = 1e-9; // a bound no ratio meets: the edge steps decide
    EXPECT_TRUE(withinSeamBound(everywhere, noRatio, &exact));
    // Face +X raised by half the reference's steepest edge step: a step of its own at +X's edges,
    // nothing inside the faces.
    CubeImage seams = exact;
    for (int j = 0; j < exact.size; ++j)
        for (int i = 0; i < exact.size; ++i) {
            const std::size_t t = texelIndex({0, i, j}, exact.size);
            seams.set(t, exact.texel(t) + glm::vec3(float(0.5 * e.edge)));
        }
    EXPECT_GT(steepestSteps(seams).edge, 1.1 * e.edge);
    EXPECT_DOUBLE_EQ(steepestSteps(seams).quarterLine, e.quarterLine);
    EXPECT_FALSE(withinSeamBound(seams, noRatio, &exact));
}
