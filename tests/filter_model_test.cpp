// The shared sampling model: seamless footprints, the corner rule, the pyramid, frames, the table
// filter and importance sampling in value and impulse form, and table files.
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "probe/cpu_filter.h"
#include "probe/cube_footprint.h"
#include "probe/error.h"
#include "probe/fis.h"
#include "probe/frame.h"
#include "probe/pyramid.h"
#include "probe/stratified_texels.h"
#include "probe/synthetic.h"
#include "probe/table_filter.h"
#include "probe/table_io.h"

namespace probe {
namespace {

// A table with positive weights and taps spread around the frame's z axis.
TapTable randomTable(int faceSize, int levelCount, int taps, TableForm form, unsigned seed) {
    TapTable table = emptyTable(faceSize, levelCount, taps, form, RoughnessMapping::gltf, {});
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> offset(-0.3, 0.3), level(0.0, levelCount), weight(0.5, 1.0), small(0.0, 0.2);
    const int k = coefficientCount(form);
    for (TableLevel& l : table.levels)
        for (int f = 0; f < kFrameCount; ++f)
            for (int t = 0; t < taps; ++t) {
                double* c = &l.coefficients[table.offset(f, t)];
                const double base[kTapParameterCount] = {offset(rng), offset(rng), 1.0, level(rng), weight(rng)};
                for (int p = 0; p < kTapParameterCount; ++p) {
                    c[p * k] = base[p];
                    for (int j = 1; j < k; ++j) c[p * k + j] = p == tapWeight ? small(rng) : 0.5 * offset(rng);
                }
            }
    return table;
}

double footprintValue(const Footprint& f, const std::vector<double>& image) {
    double v = 0.0;
    for (int k = 0; k < f.count; ++k) v += f.taps[k].weight * image[f.taps[k].index];
    return v;
}

std::vector<double> randomImage(int size, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> value(0.0, 1.0);
    std::vector<double> image(texelCount(size));
    for (double& v : image) v = value(rng);
    return image;
}

TEST(CubeSampling, FootprintWeightsArePositiveAndSumToOne) {
    std::mt19937 rng(1);
    for (int size : {1, 2, 4, 16}) {
        std::uniform_real_distribution<double> coordinate(0.0, size), axis(-1.0, 1.0);
        for (int n = 0; n < 2000; ++n) {
            const Footprint a = bilinearFootprint(size, n % kFaceCount, coordinate(rng), coordinate(rng));
            const Footprint b = bilinearFootprint(size, std::array<double, 3>{axis(rng), axis(rng), axis(rng)});
            for (const Footprint& f : {a, b}) {
                double sum = 0.0;
                for (int k = 0; k < f.count; ++k) {
                    EXPECT_GE(f.taps[k].weight, 0.0);
                    EXPECT_LT(f.taps[k].index, texelCount(size));
                    sum += f.taps[k].weight;
                }
                EXPECT_NEAR(sum, 1.0, 1e-12);
            }
        }
    }
}

// A point on a cube edge (or corner) read through each face it lies on gives the same value.
TEST(CubeSampling, SeamlessAcrossEdgesAndCorners) {
    for (int size : {1, 2, 8}) {
        const std::vector<double> image = randomImage(size, 7);
        for (int face = 0; face < kFaceCount; ++face)
            for (double s : {-1.0, 1.0})
                for (double t : {-1.0, -0.6, 0.1, 0.77, 1.0})
                    for (bool alongV : {false, true}) {
                        const glm::dvec3 p = alongV ? faceUvToCubePoint(face, t, s) : faceUvToCubePoint(face, s, t);
                        const std::array<double, 3> d{p.x, p.y, p.z};
                        double first = -1.0;
                        for (int other = 0; other < kFaceCount; ++other) {
                            const glm::dvec3 n = faceUvToCubePoint(other, 0.0, 0.0);
                            if (glm::dot(n, p) < 1.0 - 1e-12) continue; // p is not on that face
                            double u, v;
                            faceCoordinates(other, d, u, v);
                            const double value =
                                footprintValue(bilinearFootprint(size, other, (u + 1.0) * 0.5 * size, (v + 1.0) * 0.5 * size), image);
                            if (first < 0.0) first = value;
                            EXPECT_NEAR(value, first, 1e-12) << "size " << size << " face " << face << " other " << other;
                        }
                    }
    }
}

TEST(CubeSampling, CornerTexelIsTheAverageOfTheOtherThree) {
    const int size = 4;
    // A quarter texel inside the corner of face 0: the footprint's missing texel weighs 1/16.
    const Footprint f = bilinearFootprint(size, 0, 0.25, 0.25);
    ASSERT_EQ(f.count, 3);
    const std::uint32_t corner = static_cast<std::uint32_t>(texelIndex({0, 0, 0}, size));
    for (int k = 0; k < f.count; ++k) {
        const double expected = (f.taps[k].index == corner ? 0.5625 : 0.1875) + 0.0625 / 3.0;
        EXPECT_NEAR(f.taps[k].weight, expected, 1e-15);
    }
    // Exactly at the cube corner the three texels weigh 1/3 each.
    const Footprint c = bilinearFootprint(size, 0, 0.0, 0.0);
    ASSERT_EQ(c.count, 3);
    for (int k = 0; k < c.count; ++k) EXPECT_NEAR(c.taps[k].weight, 1.0 / 3.0, 1e-15);
}

TEST(CubeSampling, TrilinearLerpsAndClampsLevels) {
    const CubeLevels pyramid = buildPyramid(skyProbe(8), PyramidSettings{});
    const glm::dvec3 d = glm::normalize(glm::dvec3(0.3, -0.8, 0.5));
    const glm::dvec3 a = sampleBilinear(pyramid[1], d), b = sampleBilinear(pyramid[2], d);
    const glm::dvec3 mid = sampleTrilinear(pyramid, d, 1.25);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mid[c], 0.75 * a[c] + 0.25 * b[c], 1e-12);
    EXPECT_EQ(sampleTrilinear(pyramid, d, -3.0), sampleBilinear(pyramid[0], d));
    EXPECT_EQ(sampleTrilinear(pyramid, d, 99.0), sampleBilinear(pyramid.back(), d));
}

TEST(Pyramid, ConstantStaysConstant) {
    for (PyramidKind kind : {PyramidKind::bspline, PyramidKind::box})
        for (PyramidWeighting weighting : {PyramidWeighting::solidAngle, PyramidWeighting::inverseSolidAngle}) {
            const CubeLevels pyramid = buildPyramid(constantProbe(16, glm::vec3(0.5f, 2.0f, 7.0f)), {kind, weighting});
            ASSERT_EQ(pyramid.size(), 5u);
            EXPECT_EQ(pyramid.back().size, 1);
            for (const CubeImage& level : pyramid)
                for (std::size_t t = 0; t < texelCount(level.size); ++t) {
                    EXPECT_NEAR(level.texel(t).r, 0.5, 0.5e-6);
                    EXPECT_NEAR(level.texel(t).g, 2.0, 2e-6);
                    EXPECT_NEAR(level.texel(t).b, 7.0, 7e-6);
                }
        }
}

TEST(Pyramid, BsplineRowsAreOneThreeThreeOneInTheFaceInterior) {
    const DownsampleOperator op = downsampleOperator(16, {PyramidKind::bspline, PyramidWeighting::solidAngle});
    const std::uint32_t row = static_cast<std::uint32_t>(texelIndex({4, 3, 4}, 8));
    ASSERT_EQ(op.rowStart[row + 1] - op.rowStart[row], 16u);
    double sum = 0.0, corner = 0.0;
    for (std::uint32_t e = op.rowStart[row]; e < op.rowStart[row + 1]; ++e) {
        sum += op.entries[e].weight;
        if (op.entries[e].index == texelIndex({4, 5, 7}, 16)) corner = op.entries[e].weight;
    }
    EXPECT_NEAR(sum, 1.0, 1e-15);
    EXPECT_NEAR(corner, 1.0 / 64.0, 2e-3); // (1/8)^2 up to the Jacobian weighting
}

TEST(Pyramid, PushBackIsTheTransposeOfPullUp) {
    const int size = 8;
    const std::vector<DownsampleOperator> ops = pyramidOperators(size, {});
    const int levels = pyramidLevelCount(size);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    std::vector<std::vector<double>> up(levels), back(levels);
    for (int k = 0; k < levels; ++k) {
        up[k].assign(texelCount(size >> k), 0.0);
        back[k].resize(texelCount(size >> k));
        for (double& v : back[k]) v = value(rng);
    }
    for (double& v : up[0]) v = value(rng);
    double pyramidDot = 0.0;
    pullUpFromBase(ops, up, levels - 1);
    for (int k = 0; k < levels; ++k) pyramidDot += std::inner_product(up[k].begin(), up[k].end(), back[k].begin(), 0.0);
    pushBackToBase(ops, back, levels - 1);
    EXPECT_NEAR(std::inner_product(up[0].begin(), up[0].end(), back[0].begin(), 0.0), pyramidDot, 1e-10);
}

TEST(Frame, SomeFrameAlwaysCounts) {
    for (int size : {1, 2, 4, 8, 16, 64})
        for (int face = 0; face < kFaceCount; ++face)
            for (int j = 0; j < size; ++j)
                for (int i = 0; i < size; ++i) {
                    const glm::dvec3 d = texelCubePoint({face, i, j}, size);
                    double sum = 0.0;
                    for (int axis = 0; axis < kFrameCount; ++axis) sum += std::max(frameSetup(d, axis).weight, 0.0);
                    EXPECT_GE(sum, 2.0) << face << " " << i << " " << j;
                }
}

TEST(Frame, PolynomialDomainFollowsTheSquareBoundary) {
    // Frame Z on face +X (d = (1, y, z)): x = d_x = 1, y = d_y, so x' = 1 and theta = -y' = -d_y / 1.
    const FrameSetup f = frameSetup({1.0, 0.4, 0.2}, 2);
    EXPECT_DOUBLE_EQ(f.weight, 1.0);
    EXPECT_NEAR(f.theta2, 0.16, 1e-15);
    EXPECT_NEAR(f.phi2, 0.04, 1e-15);
    // On the frame's own pole face phi = max(|x|, |y|).
    const FrameSetup pole = frameSetup({0.9, -0.3, 1.0}, 2);
    EXPECT_NEAR(pole.weight, 0.6, 1e-12);
    EXPECT_NEAR(pole.phi2, 0.81, 1e-15);
    // The frame basis is orthonormal with z along R.
    EXPECT_NEAR(glm::dot(f.x, f.y), 0.0, 1e-15);
    EXPECT_NEAR(glm::dot(f.x, f.z), 0.0, 1e-15);
    EXPECT_NEAR(glm::length(f.y), 1.0, 1e-15);
}

TEST(TableFilter, ConstantStaysConstant) {
    for (TableForm form : {TableForm::constant, TableForm::quadratic}) {
        const TapTable table = randomTable(16, 4, 4, form, 11);
        const CubeLevels out = tableFilter(constantProbe(16, glm::vec3(3.0f)), table);
        ASSERT_EQ(out.size(), 4u);
        for (int m = 0; m < 4; ++m) {
            EXPECT_EQ(out[m].size, 16 >> m);
            for (float v : out[m].rgb) EXPECT_NEAR(v, 3.0, 3e-6);
        }
    }
}

TEST(Fis, ConstantStaysConstant) {
    for (PyramidKind kind : {PyramidKind::bspline, PyramidKind::box}) {
        FisSettings settings;
        settings.samples = 16;
        settings.pyramid.kind = kind;
        const CubeLevels out = fisFilter(constantProbe(16, glm::vec3(3.0f)), 4, RoughnessMapping::gltf, settings);
        for (const CubeImage& level : out)
            for (float v : level.rgb) EXPECT_NEAR(v, 3.0, 3e-6);
    }
}

// Running the value form on an impulse probe at base texel t gives w(R, t) of the impulse form.
void expectImpulseMatchesValue(const TapGenerator& generator, PyramidSettings pyramidSettings, int faceSize, int levels) {
    const std::vector<DownsampleOperator> ops = pyramidOperators(faceSize, pyramidSettings);
    const Texel outputs[] = {{0, 0, 0}, {2, 1, 0}, {5, 1, 1}};
    for (int m = 1; m < levels; ++m)
        for (Texel r : outputs) {
            const int size = faceSize >> m;
            r.i = std::min(r.i, size - 1);
            r.j = std::min(r.j, size - 1);
            const std::vector<double> w = impulseWithTaps(ops, faceSize, m, r, generator);
            EXPECT_NEAR(std::accumulate(w.begin(), w.end(), 0.0), 1.0, 1e-9);
            const std::size_t peak = static_cast<std::size_t>(std::max_element(w.begin(), w.end()) - w.begin());
            for (std::size_t t : {peak, (peak + 1) % w.size(), std::size_t{5}}) {
                Texel source{static_cast<int>(t / (faceSize * faceSize)), static_cast<int>(t % faceSize),
                             static_cast<int>(t / faceSize % faceSize)};
                const CubeLevels pyramid = buildPyramid(impulseProbe(faceSize, source), pyramidSettings);
                const CubeLevels value = filterWithTaps(pyramid, levels, generator);
                EXPECT_NEAR(value[m].texel(texelIndex(r, size)).r, w[t], 1e-6 * (1.0 + w[t]));
            }
        }
}

TEST(TableFilter, ImpulseFormEqualsValueForm) {
    const TapTable table = randomTable(8, 4, 4, TableForm::quadratic, 5);
    expectImpulseMatchesValue(tableTapGenerator(table), table.pyramid, 8, 4);
}

TEST(Fis, ImpulseFormEqualsValueForm) {
    FisSettings settings;
    settings.samples = 8;
    expectImpulseMatchesValue(fisTapGenerator(8, 4, RoughnessMapping::gltf, settings), settings.pyramid, 8, 4);
}

TEST(TableFilter, CopyLevelIsTheSource) {
    const TapTable table = randomTable(8, 3, 4, TableForm::constant, 2);
    const CubeImage source = skyProbe(8);
    EXPECT_EQ(tableFilter(source, table)[0].rgb, source.rgb);
}

std::filesystem::path tempFile(const std::string& name) { return std::filesystem::temp_directory_path() / ("probe_sampling_test_" + name); }

// Writes `content` to `path` and expects readTable to refuse it with a message naming the file and
// holding `needle`.
void expectTableRefused(const std::filesystem::path& path, const std::string& content, const std::string& needle) {
    std::ofstream(path) << content;
    try {
        readTable(path);
        ADD_FAILURE() << "accepted: " << needle;
    } catch (const ProbeError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(path.string()), std::string::npos) << message;
        EXPECT_NE(message.find(needle), std::string::npos) << message;
    }
}

// validateTableValues throws with `needle` in its message.
void expectInvalid(const TapTable& table, const std::string& needle) {
    try {
        validateTableValues(table, "table");
        ADD_FAILURE() << "accepted: " << needle;
    } catch (const ProbeError& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

// Sets the direction coefficients of `tap` in `frame` of every level to `terms` (c0, c1, c2 per
// axis) and, with `noWeight`, its weight to 0.
void setDirection(TapTable& table, int frame, int tap, const std::array<glm::dvec3, 3>& terms, bool noWeight) {
    for (TableLevel& level : table.levels)
        for (int k = 0; k < coefficientCount(table.form); ++k) {
            for (int axis = 0; axis < 3; ++axis) level.coefficients[table.offset(frame, tap, tapDirX + axis) + k] = terms[k][axis];
            if (noWeight) level.coefficients[table.offset(frame, tap, tapWeight) + k] = 0.0;
        }
}

// A tap direction is refused at an output texel where it vanishes, and so is a direction-less tap
// that the GPU reads as padding: it runs taps in groups of four, and a NaN read times a zero weight
// is still NaN.
TEST(TableValues, EveryTapTheGpuReadsHasADirectionAtEveryTexel) {
    const TapTable good = randomTable(32, 5, 8, TableForm::quadratic, 3);
    EXPECT_NO_THROW(validateTableValues(good, "table"));
    // Frame 1's tap 0 along (0, 0, theta^2 - t), t the theta^2 of one texel of level 1: zero there.
    const FrameSetup f = frameSetup(texelCubePoint({0, 2, 5}, 16), 1);
    ASSERT_GT(f.weight, 0.0);
    TapTable vanishing = good;
    setDirection(vanishing, 1, 0, {glm::dvec3(0.0, 0.0, -f.theta2), glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(0.0)}, false);
    expectInvalid(vanishing, "level 1 frame 1 tap 0 has no direction at texel");
    TapTable nearly = good; // 1e-4 long there, 7e-5 of its coefficients' size: still a direction
    setDirection(nearly, 1, 0, {glm::dvec3(1e-4, 0.0, -f.theta2), glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(0.0)}, false);
    EXPECT_NO_THROW(validateTableValues(nearly, "table"));
    TapTable padded = good; // taps 5 to 7 empty: 5 in use, so the GPU reads 5 to 7 as padding
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int tap = 5; tap < 8; ++tap) setDirection(padded, frame, tap, {}, true);
    expectInvalid(padded, "level 1 frame 0 tap 5 has no direction at texel (face 0, 0, 0) (its direction coefficients are all 0)");
    TapTable half = good; // taps 4 to 7 empty: the GPU stops after the first group
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int tap = 4; tap < 8; ++tap) setDirection(half, frame, tap, {}, true);
    EXPECT_NO_THROW(validateTableValues(half, "table"));
}

// The weight sum is checked at every output texel. Here it is negative only at the 4 texels round
// each face centre of a 256^2 table's level 1, where every frame that counts has theta and phi near
// 0; none of them is among the 512 stratified texels that a sampled check would look at.
TEST(TableValues, WeightsMustSumToAPositiveValueAtEveryTexel) {
    TapTable table = emptyTable(256, 2, 4, TableForm::quadratic, RoughnessMapping::gltf, {});
    const int size = 128;
    const double ring = 2.0 / (size * size), next = 10.0 / (size * size); // theta^2 + phi^2 of the nearest two rings
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int tap = 0; tap < 4; ++tap) {
            setDirection(table, frame, tap, {glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(0.0), glm::dvec3(0.0)}, true);
            if (tap > 0) continue;
            double* w = &table.levels[1].coefficients[table.offset(frame, tap, tapWeight)];
            w[0] = -0.5 * (ring + next); // w = theta^2 + phi^2 - (ring + next) / 2
            w[1] = w[2] = 1.0;
        }
    for (const WeightedTexel& w : stratifiedTexels(size, 512)) {
        const int c = size / 2;
        EXPECT_FALSE((w.texel.i == c - 1 || w.texel.i == c) && (w.texel.j == c - 1 || w.texel.j == c))
            << "the stratified set has a centre texel of face " << w.texel.face;
    }
    expectInvalid(table, "level 1 at texel (face 0, 63, 63): the tap weights sum to");
}

TEST(TableIo, RoundTrip) {
    TapTable table = randomTable(16, 4, 8, TableForm::quadratic, 9);
    table.mapping = RoughnessMapping::authors;
    table.pyramid = {PyramidKind::box, PyramidWeighting::inverseSolidAngle};
    table.solver = "test";
    table.fitSeconds = 1.5;
    table.levels[2].stratified = {0.125, 0.5, {3, 1, 2}};
    table.levels[2].minWeightSum = 0.75;
    const auto path = tempFile("roundtrip.json");
    std::ofstream(path) << tableToJson(table);
    const TapTable back = readTable(path);
    EXPECT_EQ(back.faceSize, 16);
    EXPECT_EQ(back.levelCount, 4);
    EXPECT_EQ(back.taps, 8);
    EXPECT_EQ(back.form, TableForm::quadratic);
    EXPECT_EQ(back.mapping, RoughnessMapping::authors);
    EXPECT_EQ(back.pyramid, table.pyramid);
    EXPECT_EQ(back.solver, "test");
    EXPECT_EQ(back.levels[2].stratified.worst, (Texel{3, 1, 2}));
    EXPECT_EQ(back.levels[2].minWeightSum, 0.75);
    for (int m = 0; m < 4; ++m) EXPECT_EQ(back.levels[m].coefficients, table.levels[m].coefficients);
    std::filesystem::remove(path);
}

// A level handed to FIS keeps its count through the file and the generated header; a count out of
// range, or at a copy level, is refused by name.
TEST(TableIo, HandOffRoundTripAndRefusals) {
    TapTable table = randomTable(16, 4, 8, TableForm::quadratic, 9);
    table.levels[2].fisSamples = 48;
    const std::string text = tableToJson(table);
    const auto path = tempFile("handoff.json");
    std::ofstream(path) << text;
    const TapTable back = readTable(path);
    for (int m = 0; m < 4; ++m) EXPECT_EQ(back.levels[m].fisSamples, m == 2 ? 48 : 0) << "level " << m;
    EXPECT_NE(tableCppHeader(table, "t").find("kFisSamples[4] = {0, 0, 48, 0};"), std::string::npos);
    EXPECT_NE(tableGlslInclude(table, "t").find("probeTableFisSamples[4] = int[](0, 0, 48, 0);"), std::string::npos);
    std::string tooMany = text;
    tooMany.replace(tooMany.find("\"fisSamples\": 48"), 16, "\"fisSamples\": 70000");
    expectTableRefused(path, tooMany, "level 2 is handed to FIS with 70000 samples");
    table.levels[2].fisSamples = 0;
    table.levels[0].fisSamples = 8; // GGX level 0: alpha 0, a copy
    EXPECT_THROW(tableToJson(table), ProbeError);
    std::filesystem::remove(path);
}

TEST(TableIo, PublishedLayoutRoundTrip) {
    for (TableForm form : {TableForm::constant, TableForm::quadratic}) {
        const TapTable table = randomTable(16, 4, 8, form, 4);
        const auto path = tempFile("published.txt");
        writePublishedTable(path, table);
        const TapTable back = importPublishedTable(path, 16, 4, 8, form, RoughnessMapping::gltf, {});
        for (int m = 0; m < 4; ++m)
            for (std::size_t k = 0; k < table.levels[m].coefficients.size(); ++k)
                EXPECT_EQ(static_cast<float>(back.levels[m].coefficients[k]), static_cast<float>(table.levels[m].coefficients[k]));
        // The published index order: parameter 3 (level), coefficient 0, frame 1, tap 5 -> vec4 (1 * 2 + 1), .y
        const std::vector<float> layout = publishedLevelLayout(table, 1);
        const int k = coefficientCount(form);
        EXPECT_EQ(layout[((3 * k + 0) * 6 + 3) * 4 + 1], static_cast<float>(table.levels[1].coefficients[table.offset(1, 5, 3)]));
        EXPECT_THROW(importPublishedTable(path, 16, 4, 4, form, RoughnessMapping::gltf, {}), ProbeError);
        std::filesystem::remove(path);
    }
}

TEST(TableIo, TruncatedOrWrongLayoutIsRefused) {
    const TapTable table = randomTable(16, 4, 4, TableForm::quadratic, 1);
    const std::string text = tableToJson(table);
    const auto path = tempFile("bad.json");
    const auto expectRefused = [&](const std::string& content, const std::string& needle) { expectTableRefused(path, content, needle); };
    expectRefused(text.substr(0, text.size() / 2), "not valid JSON, or incomplete");
    std::string wrongTaps = text;
    wrongTaps.replace(wrongTaps.find("\"taps\": 4"), 9, "\"taps\": 8");
    expectRefused(wrongTaps, "coefficients");
    std::string wrongSize = text;
    wrongSize.replace(wrongSize.find("\"faceSize\": 16"), 14, "\"faceSize\": 12");
    expectRefused(wrongSize, "power of two");
    expectRefused("{\"format\": \"something else\"}", "not a probefilter-tap-table");
    std::filesystem::remove(path);
}

TEST(TableIo, GeneratedSourcesRecordInputsAndErrors) {
    TapTable table = randomTable(16, 4, 4, TableForm::quadratic, 1);
    table.levels[1].stratified = {0.0123, 0.2, {0, 0, 0}};
    const std::string header = tableCppHeader(table, "gltf16_quad4");
    const std::string glsl = tableGlslInclude(table, "gltf16_quad4");
    for (const std::string* s : {&header, &glsl}) {
        EXPECT_NE(s->find("face size 16, 4 levels, 4 taps"), std::string::npos);
        EXPECT_NE(s->find("0.01230"), std::string::npos);
        EXPECT_NE(s->find("bspline weighted by solid-angle"), std::string::npos);
    }
    // 4 levels x 5 parameters x 3 coefficients x 3 frames x 4 taps.
    EXPECT_NE(header.find("kCoefficients[720]"), std::string::npos);
    EXPECT_NE(glsl.find("probeTableCoeffs[180]"), std::string::npos);
}

} // namespace
} // namespace probe
