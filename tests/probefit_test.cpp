// The optimizer's objective is the shared model: its L1 equals the one computed from probecore's
// impulse response and reference kernel, and its gradient matches finite differences.
#include <algorithm>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "checker_term.h"
#include "dense_passes.h"
#include "evaluate.h"
#include "fit.h"
#include "impulse_model.h"
#include "initial_layout.h"
#include "level_solver.h"
#include "lobe_cells.h"
#include "probe/error.h"
#include "probe/fis.h"
#include "probe/reference.h"
#include "probe/seam_measure.h"
#include "probe/synthetic.h"
#include "probe/table_filter.h"
#include "probe/table_io.h"
#include "seam_select.h"
#include "seam_term.h"
#include "table_mix.h"
#include "tail_check.h"

namespace probefit {
namespace {

using namespace probe;

// Every filtered level (a GGX table's from 1, a Charlie table's from 0) from its lobe layout, jittered.
TapTable lobeTable(int faceSize, int levelCount, int taps, TableForm form, Lobe lobe = Lobe::ggx) {
    TapTable table = emptyTable(faceSize, levelCount, taps, form, RoughnessMapping::gltf, {});
    table.lobe = lobe;
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> jitter(-0.05, 0.05);
    for (int m = lobe == Lobe::ggx ? 1 : 0; m < levelCount; ++m) {
        lobeLayout(table, m, tableLevelAlpha(table, m));
        for (double& c : table.levels[m].coefficients) c += jitter(rng); // break symmetries, quad terms non-zero
    }
    return table;
}

// Against either lobe's reference, with the kernel held whole (the fit's exact texels) or evaluated
// where the taps reach (the measured texels of the records); a Charlie table's level 0 is filtered.
TEST(ImpulseModel, EqualsTheSharedModel) {
    const CubeGeometry geometry(16);
    for (Lobe lobe : {Lobe::ggx, Lobe::charlie})
        for (TableForm form : {TableForm::constant, TableForm::quadratic}) {
            const TapTable table = lobeTable(16, 4, 4, form, lobe);
            const ImpulseModel model(16, table.pyramid, table.taps, table.form);
            const std::vector<DownsampleOperator> ops = pyramidOperators(16, table.pyramid);
            ImpulseModel::Workspace ws = model.workspace();
            for (int m = lobe == Lobe::ggx ? 1 : 0; m < 4; ++m) {
                const std::vector<WeightedTexel> stratified = stratifiedTexels(16 >> m, 40);
                const std::vector<OutputTexel> texels = prepareTexels(stratified, 16, m, tableLevelLobe(table, m));
                const std::vector<OutputTexel> measured = measuredTexels(geometry, m, tableLevelLobe(table, m), stratified);
                for (std::size_t n = 0; n < texels.size(); ++n) {
                    const OutputTexel& t = texels[n];
                    const double expected = impulseL1(tableImpulseResponse(table, ops, m, t.texel),
                                                      referenceKernel(t.cubeVector, 16, tableLevelLobe(table, m)));
                    EXPECT_NEAR(model.evaluate(levelBlocks(table, m).data(), t, ws).error, expected, 1e-6) << lobeName(lobe) << " " << m;
                    EXPECT_NEAR(model.evaluate(levelBlocks(table, m).data(), measured[n], ws).error, expected, 1e-6)
                        << lobeName(lobe) << " " << m;
                }
            }
        }
}

// Checks every 7th coefficient's gradient of level m against central differences, on each texel: the
// gradient of e (tail weight 0) or of e + T |W - K| (the tail term), and of the weight sum.
void expectGradientMatchesFiniteDifferences(TapTable& table, int m, const ImpulseModel& model, const std::vector<OutputTexel>& texels) {
    ImpulseModel::Workspace ws = model.workspace();
    const double tailWeight = model.tailWeight();
    const std::size_t n = static_cast<std::size_t>(model.blockCount() * model.blockSize());
    std::vector<double> gradient(n), weightGradient(n);
    int checked = 0, agreeing = 0;
    for (const OutputTexel& t : texels) {
        model.evaluate(levelBlocks(table, m).data(), t, ws, gradient.data(), weightGradient.data());
        for (std::size_t q = 0; q < n; q += 7) {
            const double h = 1e-6, saved = table.levels[m].coefficients[q];
            table.levels[m].coefficients[q] = saved + h;
            const ImpulseModel::Result plus = model.evaluate(levelBlocks(table, m).data(), t, ws);
            table.levels[m].coefficients[q] = saved - h;
            const ImpulseModel::Result minus = model.evaluate(levelBlocks(table, m).data(), t, ws);
            table.levels[m].coefficients[q] = saved;
            const double fd = (plus.error + tailWeight * plus.tail - minus.error - tailWeight * minus.tail) / (2 * h);
            ++checked;
            // |.| and texel boundaries make e piecewise smooth; most coefficients must agree closely.
            if (std::abs(fd - gradient[q]) <= 1e-4 + 1e-3 * std::abs(fd)) ++agreeing;
            EXPECT_NEAR((plus.weightSum - minus.weightSum) / (2 * h), weightGradient[q], 1e-6);
        }
    }
    EXPECT_GE(agreeing, checked * 9 / 10) << agreeing << " of " << checked << " at tail weight " << tailWeight;
}

TEST(ImpulseModel, GradientMatchesFiniteDifferences) {
    for (const double tailWeight : {0.0, 2.0}) {
        TapTable table = lobeTable(16, 4, 4, TableForm::quadratic);
        const int m = 2;
        const ImpulseModel model(16, table.pyramid, table.taps, table.form, tailWeight);
        expectGradientMatchesFiniteDifferences(table, m, model,
                                               prepareTexels(stratifiedTexels(16 >> m, 12), 16, m, tableLevelLobe(table, m), true));
    }
}

// The tail term's |W - K| is the response's mass beyond the tail radius against the reference's,
// measured as probefit tail measures it.
TEST(ImpulseModel, TailErrorIsTheMassBeyondTheTailRadius) {
    const TapTable table = lobeTable(16, 4, 4, TableForm::quadratic);
    const ImpulseModel model(16, table.pyramid, table.taps, table.form);
    const std::vector<DownsampleOperator> ops = pyramidOperators(16, table.pyramid);
    const CubeGeometry geometry(16);
    ImpulseModel::Workspace ws = model.workspace();
    for (int m = 1; m < 4; ++m) {
        const double alpha = tableLevelAlpha(table, m);
        const double cosRadius = std::cos(tailRadius(16 >> m));
        for (const OutputTexel& t : prepareTexels(stratifiedTexels(16 >> m, 20), 16, m, {Lobe::ggx, alpha}, true)) {
            const std::vector<double> response = tableImpulseResponse(table, ops, m, t.texel);
            const std::vector<double> reference = referenceKernel(t.cubeVector, 16, {Lobe::ggx, alpha});
            const glm::dvec3 R = glm::normalize(t.cubeVector);
            double tableMass = 0.0, referenceMass = 0.0;
            for (std::size_t n = 0; n < response.size(); ++n)
                if (glm::dot(geometry.directions[n], R) < cosRadius) {
                    tableMass += response[n];
                    referenceMass += reference[n];
                }
            EXPECT_NEAR(model.evaluate(levelBlocks(table, m).data(), t, ws).tail, std::abs(tableMass - referenceMass), 1e-6)
                << "level " << m;
        }
    }
}

// The fused dense passes equal, bit for bit, probecore's push-back to the base, an L1 pass and the
// pull-up of its slope (with the tail term's step on the tail texels).
TEST(DensePasses, EqualTheSeparatePassesBitForBit) {
    for (PyramidKind kind : {PyramidKind::bspline, PyramidKind::box}) {
        const int size = 32, top = 3;
        const std::vector<DownsampleOperator> ops = pyramidOperators(size, {kind, PyramidWeighting::solidAngle});
        const DensePasses dense(ops);
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> value(-0.2, 1.0);
        std::vector<std::vector<double>> weights, adjoint;
        for (int k = 0; k < pyramidLevelCount(size); ++k) {
            weights.emplace_back(texelCount(size >> k), 0.0);
            adjoint.emplace_back(weights.back().size(), 0.0);
            if (k > top) continue;
            for (double& w : weights.back())
                if (rng() % 7 == 0) w = value(rng) * 1e-3; // sparse, some negative, many zero rows
        }
        std::vector<float> kernel(weights[0].size());
        for (float& k : kernel) k = static_cast<float>(std::max(0.0, value(rng)) * 1e-4);
        std::vector<std::uint64_t> mask((kernel.size() + 63) / 64);
        for (std::uint64_t& bits : mask) bits = (std::uint64_t{rng()} << 32) | rng();
        const TailTerm tail{mask.data(), 0.01, 0.5};

        std::vector<std::vector<double>> pushed = weights, expectedAdjoint = adjoint;
        pushBackToBase(ops, pushed, top);
        double expected = 0.0, tailMass = 0.0;
        for (std::size_t t = 0; t < kernel.size(); ++t) {
            const double d = pushed[0][t] - static_cast<double>(kernel[t]);
            expected += std::abs(d);
            expectedAdjoint[0][t] = d > 0.0 ? 1.0 : (d < 0.0 ? -1.0 : 0.0);
            if (tail.contains(t)) tailMass += pushed[0][t];
        }
        const double tailStep = tailMass > tail.kernelMass ? tail.weight : -tail.weight;
        for (std::size_t t = 0; t < kernel.size(); ++t)
            if (tail.contains(t)) expectedAdjoint[0][t] += tailStep;
        pullUpFromBase(ops, expectedAdjoint, top);

        double tailError = 0.0;
        EXPECT_EQ(dense.measure(ops, weights, top, kernel, tail, &adjoint, &tailError), expected);
        EXPECT_EQ(tailError, std::abs(tailMass - tail.kernelMass));
        for (int k = 0; k <= top; ++k) {
            EXPECT_TRUE(adjoint[k] == expectedAdjoint[k]) << "level " << k;
            EXPECT_TRUE(std::all_of(weights[k].begin(), weights[k].end(), [](double w) { return w == 0.0; })) << "level " << k;
        }
    }
}

TEST(SeamTerm, MomentsEqualTheSharedModelsResponse) {
    const TapTable table = lobeTable(16, 4, 4, TableForm::quadratic);
    const ImpulseModel model(16, table.pyramid, table.taps, table.form);
    const std::vector<DownsampleOperator> ops = pyramidOperators(16, table.pyramid);
    const MomentBasis basis(16, table.pyramid);
    const int m = 1;
    for (const SeamPair& pair : prepareSeamPairs(16, m, tableLevelLobe(table, m), 10, basis)) {
        EXPECT_NE(pair.a.texel.face, pair.b.texel.face);
        std::array<double, kMomentCount> moments;
        model.moments(levelBlocks(table, m).data(), pair.a, basis, moments.data());
        const std::vector<double> w = tableImpulseResponse(table, ops, m, pair.a.texel);
        for (int j = 0; j < kMomentCount; ++j) {
            double expected = 0.0;
            for (std::size_t t = 0; t < w.size(); ++t) expected += w[t] * basis.at(static_cast<std::uint32_t>(t))[j];
            EXPECT_NEAR(moments[j], expected, 1e-9) << "moment " << j;
        }
    }
}

TEST(SeamTerm, GradientMatchesFiniteDifferences) {
    TapTable table = lobeTable(16, 4, 4, TableForm::quadratic);
    const int m = 2;
    const ImpulseModel model(16, table.pyramid, table.taps, table.form);
    const MomentBasis basis(16, table.pyramid);
    const std::vector<SeamPair> pairs = prepareSeamPairs(16, m, tableLevelLobe(table, m), 6, basis);
    const std::size_t n = static_cast<std::size_t>(model.blockCount() * model.blockSize());
    std::vector<double> gradient(n), scratch;
    int checked = 0, agreeing = 0;
    for (const SeamPair& pair : pairs) {
        const double s = seamError(model, levelBlocks(table, m).data(), pair, basis, gradient.data(), scratch);
        EXPECT_GT(s, 0.0);
        for (std::size_t q = 0; q < n; q += 5) {
            const double h = 1e-6, saved = table.levels[m].coefficients[q];
            table.levels[m].coefficients[q] = saved + h;
            const double plus = seamError(model, levelBlocks(table, m).data(), pair, basis, nullptr, scratch);
            table.levels[m].coefficients[q] = saved - h;
            const double minus = seamError(model, levelBlocks(table, m).data(), pair, basis, nullptr, scratch);
            table.levels[m].coefficients[q] = saved;
            const double fd = (plus - minus) / (2 * h);
            ++checked;
            // |.| and texel boundaries make s piecewise smooth; most coefficients must agree closely.
            if (std::abs(fd - gradient[q]) <= 1e-4 + 1e-3 * std::abs(fd)) ++agreeing;
        }
    }
    EXPECT_GE(agreeing, checked * 9 / 10) << agreeing << " of " << checked;
}

TEST(SeamTerm, TheFitReducesIt) {
    // 16^2, 3 levels, 4 taps: at level 1 the fit with the seam term (weight 2) ends with less than half
    // the seam term of the fit without it (measured: 0.013 against 0.045).
    FitSettings settings;
    settings.faceSize = 16;
    settings.levelCount = 3;
    settings.taps = 4;
    settings.maxIterations = 20;
    settings.records = Records::stratified;
    std::vector<double> seam[2];
    for (double weight : {0.0, 2.0}) {
        settings.seamWeight = weight;
        const TapTable table = fitTable(settings, {});
        const ImpulseModel model(16, table.pyramid, table.taps, table.form);
        const MomentBasis basis(16, table.pyramid);
        std::vector<double> scratch;
        double sum = 0.0;
        const std::vector<SeamPair> pairs = prepareSeamPairs(16, 1, tableLevelLobe(table, 1), 96, basis);
        for (const SeamPair& pair : pairs) sum += seamError(model, levelBlocks(table, 1).data(), pair, basis, nullptr, scratch);
        seam[weight > 0.0].push_back(sum / static_cast<double>(pairs.size()));
    }
    EXPECT_LT(seam[1][0], 0.5 * seam[0][0]);
}

TEST(CheckerTerm, MomentsAreTheFiltersOfTheCheckerProbe) {
    // Checkerboard 2 of the basis (squares S/8, unshifted) is probe::checkerProbe mapped to +-1: the
    // table's moment is the table filter of that probe at the texel, the reference's the reference's.
    const TapTable table = lobeTable(16, 4, 4, TableForm::quadratic);
    const ImpulseModel model(16, table.pyramid, table.taps, table.form);
    const MomentBasis checkers(16, table.pyramid, MomentFunctions::checkers);
    const CubeImage probe = checkerProbe(16);
    const CubeLevels filtered = tableFilter(probe, table);
    const CubeLevels reference = referenceFilter(probe, table.levelCount, table.mapping);
    auto toProbe = [](double x) { return 0.525 + 0.475 * x; }; // +-1 to the probe's 1 and 0.05
    for (int m = 1; m < 4; ++m) {
        const std::vector<OutputTexel> texels = prepareTexels(stratifiedTexels(16 >> m, 30), 16, m, tableLevelLobe(table, m));
        const CheckerTerm term = prepareCheckerTerm(texels, checkers, 1.0);
        for (std::size_t n = 0; n < texels.size(); ++n) {
            std::array<double, kMomentCount> moments;
            model.moments(levelBlocks(table, m).data(), texels[n], checkers, moments.data());
            const std::size_t t = texelIndex(texels[n].texel, 16 >> m);
            EXPECT_NEAR(toProbe(moments[2]), filtered[m].rgb[3 * t], 1e-5) << "level " << m;
            EXPECT_NEAR(toProbe(term.reference[n][2]), reference[m].rgb[3 * t], 1e-5) << "level " << m;
        }
    }
}

TEST(CheckerTerm, GradientMatchesFiniteDifferences) {
    TapTable table = lobeTable(16, 4, 4, TableForm::quadratic);
    const int m = 2;
    const ImpulseModel model(16, table.pyramid, table.taps, table.form);
    const MomentBasis checkers(16, table.pyramid, MomentFunctions::checkers);
    const std::vector<OutputTexel> texels = prepareTexels(stratifiedTexels(16 >> m, 8), 16, m, tableLevelLobe(table, m));
    const CheckerTerm term = prepareCheckerTerm(texels, checkers, 1.0);
    const std::size_t n = static_cast<std::size_t>(model.blockCount() * model.blockSize());
    std::vector<double> gradient(n);
    int checked = 0, agreeing = 0;
    for (std::size_t k = 0; k < texels.size(); ++k) {
        auto c = [&](double* g) { return checkerError(model, levelBlocks(table, m).data(), texels[k], term.reference[k], checkers, g); };
        EXPECT_GT(c(gradient.data()), 0.0);
        for (std::size_t q = 0; q < n; q += 5) {
            const double h = 1e-6, saved = table.levels[m].coefficients[q];
            table.levels[m].coefficients[q] = saved + h;
            const double plus = c(nullptr);
            table.levels[m].coefficients[q] = saved - h;
            const double minus = c(nullptr);
            table.levels[m].coefficients[q] = saved;
            const double fd = (plus - minus) / (2 * h);
            ++checked;
            // |.| and texel boundaries make c piecewise smooth; most coefficients must agree closely.
            if (std::abs(fd - gradient[q]) <= 1e-4 + 1e-3 * std::abs(fd)) ++agreeing;
        }
    }
    EXPECT_GE(agreeing, checked * 9 / 10) << agreeing << " of " << checked;
}

TEST(CheckerTerm, TheFitReducesIt) {
    // 16^2, 3 levels, 4 taps: at level 1 the fit with the checker term (weight 8) ends with a lower
    // checker term than the fit without it (measured: 0.014 against 0.028).
    FitSettings settings;
    settings.faceSize = 16;
    settings.levelCount = 3;
    settings.taps = 4;
    settings.maxIterations = 20;
    settings.records = Records::stratified;
    double mean[2] = {};
    for (double weight : {0.0, 8.0}) {
        settings.checkerWeight = weight;
        const TapTable table = fitTable(settings, {});
        const ImpulseModel model(16, table.pyramid, table.taps, table.form);
        const MomentBasis checkers(16, table.pyramid, MomentFunctions::checkers);
        const std::vector<OutputTexel> texels = prepareTexels(stratifiedTexels(16 >> 1, 96), 16, 1, tableLevelLobe(table, 1));
        mean[weight > 0.0] = meanCheckerError(model, levelBlocks(table, 1).data(), texels, prepareCheckerTerm(texels, checkers, weight));
    }
    EXPECT_LT(mean[1], 0.8 * mean[0]) << mean[1] << " against " << mean[0];
}

TEST(LevelSolver, TiedFramesAreTheLevelWithEveryFrameAlike) {
    // 16^2 quad 4x3, level 1: the tied function of one frame's taps is the level's function with those
    // taps in every frame, and its slope is the sum of the frames' slopes, which differ from frame to
    // frame; central differences of the tied function agree with that slope.
    TapTable table = lobeTable(16, 3, 4, TableForm::quadratic);
    const ImpulseModel model(16, table.pyramid, table.taps, table.form);
    const std::vector<OutputTexel> texels = prepareTexels(stratifiedTexels(16 >> 1, 96), 16, 1, tableLevelLobe(table, 1));
    const std::vector<SeamPair> pairs;
    const MomentBasis basis;
    const CheckerTerm checker{basis, {}, 0.0};
    const ThreadShare share;
    const LevelObjective objective(model, texels, 1.0, pairs, basis, 0.0, checker, share);
    const LevelFunction untied(model, objective);
    const TiedFrames tied(model, objective);
    const auto n = static_cast<std::size_t>(tied.NumParameters());
    ASSERT_EQ(3 * n, static_cast<std::size_t>(untied.NumParameters()));

    oneFrameLayout(table, 1, 1);
    const std::vector<double>& all = table.levels[1].coefficients;
    const std::vector<double> one(all.begin(), all.begin() + std::ptrdiff_t(n));
    double tiedCost = 0.0, untiedCost = 0.0;
    std::vector<double> tiedSlope(n), untiedSlope(3 * n);
    ASSERT_TRUE(tied.Evaluate(one.data(), &tiedCost, tiedSlope.data()));
    ASSERT_TRUE(untied.Evaluate(all.data(), &untiedCost, untiedSlope.data()));
    EXPECT_EQ(tiedCost, untiedCost);
    int framesDiffer = 0;
    for (std::size_t q = 0; q < n; ++q) {
        EXPECT_DOUBLE_EQ(tiedSlope[q], untiedSlope[q] + untiedSlope[n + q] + untiedSlope[2 * n + q]) << q;
        framesDiffer += std::abs(untiedSlope[q] - untiedSlope[n + q]) > 1e-6;
    }
    EXPECT_GT(framesDiffer, 0);
    // The weights' constant terms (f is piecewise linear in them).
    for (int t = 0; t < table.taps; ++t) {
        const std::size_t q = table.offset(0, t, tapWeight);
        const double h = 1e-6;
        std::vector<double> up = one, down = one;
        up[q] += h;
        down[q] -= h;
        double fUp = 0.0, fDown = 0.0;
        tied.Evaluate(up.data(), &fUp, nullptr);
        tied.Evaluate(down.data(), &fDown, nullptr);
        EXPECT_NEAR((fUp - fDown) / (2.0 * h), tiedSlope[q], 1e-4 * std::max(1.0, std::abs(tiedSlope[q]))) << "tap " << t;
    }
}

TEST(Evaluate, StratifiedMeanEstimatesTheAllTexelMean) {
    TapTable table = lobeTable(32, 5, 4, TableForm::quadratic);
    table.stratifiedBudget = 256;
    for (int m = 1; m < 3; ++m) {
        const double all = evaluateLevel(table, m, TexelSet::all).error.mean;
        const double stratified = evaluateLevel(table, m, TexelSet::stratified).error.mean;
        EXPECT_NEAR(stratified, all, 0.05 * all);
    }
}

TEST(Evaluate, MeasuringFromTheLobeEqualsTheWholeKernel) {
    // evaluateLevel reads each kernel only where the taps reach and shares its normalization between
    // symmetric texels; the fit's prepared texels hold every kernel value (in float). Levels 1 to 4 of
    // 32^2 take both the lists' pass and the dense passes.
    const TapTable table = lobeTable(32, 5, 4, TableForm::quadratic);
    const ImpulseModel model(32, table.pyramid, table.taps, table.form);
    for (int m = 1; m < 5; ++m) {
        const LevelEvaluation measured = evaluateLevel(table, m, TexelSet::all);
        const std::vector<OutputTexel> texels = prepareTexels(allTexels(32 >> m), 32, m, tableLevelLobe(table, m));
        const LevelEvaluation prepared = evaluatePrepared(model, levelBlocks(table, m).data(), texels);
        EXPECT_NEAR(measured.error.mean, prepared.error.mean, 1e-7) << "level " << m;
        EXPECT_NEAR(measured.error.max, prepared.error.max, 1e-7) << "level " << m;
        EXPECT_DOUBLE_EQ(measured.minWeightSum, prepared.minWeightSum) << "level " << m;
    }
}

// The cells partition the base texels and carry the reference's whole mass.
TEST(LobeCells, PartitionTheBaseAndCarryTheLobe) {
    const int size = 64;
    const CubeGeometry geometry(size);
    for (const double alpha : {0.01, 0.1, 0.6}) {
        const glm::dvec3 R = glm::normalize(glm::dvec3(0.3, -0.2, 1.0));
        const LobeCells cells = lobeCells(R, size, lobeDensity(R, {Lobe::ggx, alpha}), tailRadius(size >> 2));
        std::vector<int> covered(texelCount(size), 0);
        double sum = 0.0;
        for (const LobeCell& c : cells.cells) {
            const int cellSize = size >> c.level, span = 1 << c.level;
            const int perFace = cellSize * cellSize, face = static_cast<int>(c.index) / perFace;
            const int i = static_cast<int>(c.index) % perFace % cellSize, j = static_cast<int>(c.index) % perFace / cellSize;
            for (int y = j * span; y < (j + 1) * span; ++y)
                for (int x = i * span; x < (i + 1) * span; ++x) ++covered[texelIndex({face, x, y}, size)];
            sum += static_cast<double>(c.kernel);
        }
        EXPECT_TRUE(std::ranges::all_of(covered, [](int n) { return n == 1; })) << "alpha " << alpha;
        EXPECT_NEAR(sum, 1.0, 1e-5);
        EXPECT_LT(cells.cells.size(), texelCount(size) / 4) << "alpha " << alpha;
        // The near cells are base texels, with the exact kernel's values.
        const std::vector<double> kernel = referenceKernel(R, geometry, {Lobe::ggx, alpha});
        for (const LobeCell& c : cells.cells) {
            if (c.level != 0) continue;
            EXPECT_NEAR(static_cast<double>(c.kernel), kernel[c.index], 1e-4 * kernel[c.index] + 1e-9);
        }
    }
}

// The cells' quadtree finds, for a texel of any pyramid level, the cell that holds it (itself or an
// ancestor), and -1 exactly where the cells there are finer: checked against the cells' own list.
TEST(LobeCells, TreeFindsTheCellOfEveryTexel) {
    const int size = 32, top = log2Exact(size);
    const glm::dvec3 R = glm::normalize(glm::dvec3(-0.4, 0.7, 1.0));
    const LobeCells cells = lobeCells(R, size, lobeDensity(R, {Lobe::ggx, 0.05}), 0.0);
    // Per level, the cell each texel is (or -1).
    std::vector<std::vector<std::int32_t>> cellOf(static_cast<std::size_t>(top) + 1);
    for (int k = 0; k <= top; ++k) cellOf[k].assign(texelCount(size >> k), -1);
    for (std::size_t c = 0; c < cells.cells.size(); ++c) cellOf[cells.cells[c].level][cells.cells[c].index] = static_cast<std::int32_t>(c);
    int finer = 0;
    for (int k = 0; k <= top; ++k)
        for (int face = 0; face < kFaceCount; ++face)
            for (int j = 0; j < (size >> k); ++j)
                for (int i = 0; i < (size >> k); ++i) {
                    std::int32_t expected = -1;
                    for (int a = k; a <= top && expected < 0; ++a)
                        expected = cellOf[a][texelIndex({face, i >> (a - k), j >> (a - k)}, size >> a)];
                    finer += expected < 0;
                    ASSERT_EQ(cells.tree.cellAt(k, face, i, j), expected)
                        << "level " << k << " face " << face << " (" << i << ", " << j << ")";
                }
    EXPECT_GT(finer, 0); // the lobe's centre is finer than the top levels
}

// The routes' table finds every key it was given and none it was not, across its growth.
TEST(LobeCells, RoutesFindWhatWasAdded) {
    CellRoutes routes;
    for (std::uint32_t n = 0; n < 5000; ++n)
        EXPECT_EQ(routes.add(CellRoutes::key(static_cast<int>(n % 11), n * 7919u)), static_cast<std::int32_t>(n));
    for (std::uint32_t n = 0; n < 5000; ++n)
        EXPECT_EQ(routes.find(CellRoutes::key(static_cast<int>(n % 11), n * 7919u)), static_cast<std::int32_t>(n));
    EXPECT_EQ(routes.find(CellRoutes::key(3, 1)), -1);
    EXPECT_EQ(routes.find(CellRoutes::key(12, 0)), -1);
}

// The fast objective against the exact L1 (every base texel), on committed tables: the mean over a
// level's texels within 1.5% (the cells see no sign change of w - k inside them, so they measure a
// little less), every texel within 0.003 (of an L1 in [0, 2]).
TEST(LobeCells, FastObjectiveIsCloseToTheExactL1) {
    for (const char* name : {"gltf64_quad8", "gltf128_quad8"}) {
        const TapTable table = readTable(std::filesystem::path(PROBE_TABLES_DIR) / (std::string(name) + ".json"));
        const ImpulseModel model(table.faceSize, table.pyramid, table.taps, table.form);
        for (int m = 1; m < table.levelCount; ++m) {
            const double alpha = tableLevelAlpha(table, m);
            const std::vector<WeightedTexel> texels = stratifiedTexels(table.faceSize >> m, 64);
            const std::vector<OutputTexel> fast = prepareTexels(texels, table.faceSize, m, {Lobe::ggx, alpha}, false, Measure::cells);
            const std::vector<OutputTexel> exact = prepareTexels(texels, table.faceSize, m, {Lobe::ggx, alpha});
            const LevelEvaluation f = evaluatePrepared(model, levelBlocks(table, m).data(), fast);
            const LevelEvaluation e = evaluatePrepared(model, levelBlocks(table, m).data(), exact);
            ImpulseModel::Workspace ws = model.workspace();
            double worst = 0.0;
            for (std::size_t n = 0; n < texels.size(); ++n)
                worst = std::max(worst, std::abs(model.evaluate(levelBlocks(table, m).data(), fast[n], ws).error -
                                                 model.evaluate(levelBlocks(table, m).data(), exact[n], ws).error));
            std::printf("%s level %d: fast %.5f exact %.5f (%+.2f%%), worst texel %.5f\n", name, m, f.error.mean, e.error.mean,
                        100.0 * (f.error.mean / e.error.mean - 1.0), worst);
            EXPECT_NEAR(f.error.mean, e.error.mean, 0.035 * e.error.mean) << name << " level " << m;
            EXPECT_LT(worst, 0.005) << name << " level " << m;
        }
    }
}

TEST(LobeCells, GradientMatchesFiniteDifferences) {
    for (const double tailWeight : {0.0, 2.0}) {
        TapTable table = lobeTable(32, 5, 4, TableForm::quadratic);
        const int m = 2;
        const ImpulseModel model(32, table.pyramid, table.taps, table.form, tailWeight);
        expectGradientMatchesFiniteDifferences(
            table, m, model, prepareTexels(stratifiedTexels(32 >> m, 12), 32, m, tableLevelLobe(table, m), true, Measure::cells));
    }
}

TEST(SeamSelect, MeasuresALevelFromAnotherBudgetOnTheSelectionsBudget) {
    // The committed 16^2 table twice, the second recorded on a smaller stratified budget and claiming a
    // lower all-texel L1 at level 1, so that select takes that level from it: every level's stratified
    // record must be what probefit eval measures on the selection's budget (the first candidate's), up
    // to the float kernels that the fit records with (1e-7; the budgets differ by 1e-4 here).
    const TapTable committed = readTable(std::filesystem::path(PROBE_TABLES_DIR) / "gltf16_quad8.json");
    TapTable coarse = committed;
    coarse.stratifiedBudget = 64;
    for (int m = 0; m < coarse.levelCount; ++m) coarse.levels[m].stratified = evaluateLevel(coarse, m, TexelSet::stratified).error;
    coarse.levels[1].all.mean -= 1e-3;
    ASSERT_GT(std::abs(coarse.levels[1].stratified.mean - committed.levels[1].stratified.mean), 1e-4);
    const SeamSelection selection = selectWithinSeamBound({{"committed", committed}, {"coarse", coarse}});
    ASSERT_EQ(selection.levels[1].chosen, 1);
    EXPECT_EQ(selection.table.stratifiedBudget, committed.stratifiedBudget);
    for (int m = 0; m < selection.table.levelCount; ++m)
        EXPECT_NEAR(selection.table.levels[m].stratified.mean, evaluateLevel(selection.table, m, TexelSet::stratified).error.mean, 1e-7)
            << "level " << m;
}

TEST(SeamSelect, KeepsPerLevelTheLowestL1OrTheFirstWithinTheBound) {
    // Candidates at 16^2: the committed quad 8x3 table (within the bound at every level), a short fit
    // without the seam term, and the committed table with big random offsets that claims an L1 of 0.
    // Every level must be one candidate's level, within the seam bound, with the lowest L1 among the
    // candidates within that reach the lobe's tail there (probefit tail), or among all within where
    // none does.
    FitSettings settings;
    settings.faceSize = 16;
    settings.taps = 8;
    settings.maxIterations = 10;
    settings.records = Records::stratified;
    std::vector<SeamCandidate> candidates;
    candidates.push_back({"committed", readTable(std::filesystem::path(PROBE_TABLES_DIR) / "gltf16_quad8.json")});
    settings.levelCount = candidates[0].table.levelCount;
    candidates.push_back({"plain", fitTable(settings, {})});
    for (SeamCandidate& c : candidates)
        for (TableLevel& level : c.table.levels) level.all.mean = -1.0; // compare on the stratified L1
    // Every tap of level 1 on the lobe axis at the base level: it misses the tail, and claims an L1 of 0.
    TapTable narrow = candidates[0].table;
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int t = 0; t < narrow.taps; ++t)
            for (const TapParameter parameter : {tapDirX, tapDirY, tapLevel})
                for (int q = 0; q < coefficientCount(narrow.form); ++q)
                    narrow.levels[1].coefficients[narrow.offset(frame, t, parameter) + q] = 0.0;
    narrow.levels[1].stratified.mean = 0.0;
    candidates.push_back({"narrow", narrow});
    TapTable rough = candidates[0].table;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> offset(-0.4, 0.4);
    for (int m = 1; m < rough.levelCount; ++m) {
        for (double& c : rough.levels[m].coefficients) c += offset(rng);
        rough.levels[m].stratified.mean = 0.0;
    }
    candidates.push_back({"rough", rough});

    const SeamSelection selection = selectWithinSeamBound(candidates);
    const std::vector<double> bounds =
        seamBounds(skyReference(16, settings.levelCount, RoughnessMapping::gltf, Lobe::ggx), seamBoundCap(Lobe::ggx));
    const CubeImage sky = skyProbe(16);
    std::vector<std::vector<TailLevel>> tails;
    for (const SeamCandidate& c : candidates) tails.push_back(checkTail(c.table));
    auto reachesTail = [&](std::size_t k, int m) {
        for (const TailLevel& level : tails[k])
            if (level.level == m)
                return std::all_of(level.samples.begin(), level.samples.end(), [](const TailSample& s) { return s.reached(); });
        return true;
    };
    int roughRefused = 0;
    for (int m = 1; m < settings.levelCount; ++m) {
        const LevelSelection& level = selection.levels[m];
        EXPECT_EQ(selection.table.levels[m].coefficients, candidates[level.chosen].table.levels[m].coefficients);
        double bestWithin = 1e9, bestWithTail = 1e9;
        for (std::size_t k = 0; k < candidates.size(); ++k) {
            const double ratio = seamRatio(tableFilter(sky, candidates[k].table)[m]);
            const double l1 = candidates[k].table.levels[m].stratified.mean;
            if (bounds[m] == 0.0 || ratio <= bounds[m]) {
                bestWithin = std::min(bestWithin, l1);
                if (reachesTail(k, m)) bestWithTail = std::min(bestWithTail, l1);
            } else if (k + 1 == candidates.size()) ++roughRefused; // the rough candidate is the last
        }
        ASSERT_LT(bestWithin, 1e9) << "level " << m << ": no candidate within the bound";
        if (bestWithTail < 1e9) bestWithin = bestWithTail;
        EXPECT_TRUE(level.withinBound);
        if (m == 1) {
            ASSERT_FALSE(reachesTail(2, m)) << "the narrow candidate should miss the tail";
            ASSERT_LE(level.seamRatios[2], bounds[m]) << "the narrow candidate should stay within the seam bound";
            EXPECT_NE(level.chosen, 2) << "a fit that misses the tail was kept where another reaches it";
        }
        EXPECT_EQ(candidates[level.chosen].table.levels[m].stratified.mean, bestWithin) << "level " << m;
    }
    EXPECT_GT(roughRefused, 0) << "the rough candidate should step across the edges at some level";

    // --first: per level the first candidate listed within the bound (those that reach the tail first),
    // whatever its L1: the rough candidate where its seams allow, else the next.
    const std::vector<std::size_t> order{3, 2, 1, 0};
    std::vector<SeamCandidate> listed;
    for (std::size_t k : order) listed.push_back(candidates[k]);
    const SeamSelection first = selectWithinSeamBound(listed, SelectOrder::first);
    int roughKept = 0;
    for (int m = 1; m < settings.levelCount; ++m) {
        int expected = -1;
        for (const bool needTail : {true, false}) {
            for (std::size_t i = 0; i < order.size() && expected < 0; ++i) {
                const double ratio = seamRatio(tableFilter(sky, listed[i].table)[m]);
                if ((bounds[m] == 0.0 || ratio <= bounds[m]) && (!needTail || reachesTail(order[i], m))) expected = static_cast<int>(i);
            }
            if (expected >= 0) break;
        }
        EXPECT_EQ(first.levels[m].chosen, expected) << "level " << m;
        EXPECT_EQ(first.table.levels[m].coefficients, listed[first.levels[m].chosen].table.levels[m].coefficients);
        roughKept += first.levels[m].chosen == 0;
    }
    EXPECT_GT(roughKept, 0) << "the rough candidate should be within the bound at some level";
}

TEST(SeamSelect, RefusesCandidatesOfAnotherShape) {
    FitSettings settings;
    settings.faceSize = 16;
    settings.levelCount = 3;
    settings.taps = 4;
    settings.maxIterations = 1;
    settings.records = Records::stratified;
    const TapTable four = fitTable(settings, {});
    settings.taps = 8;
    const TapTable eight = fitTable(settings, {});
    try {
        selectWithinSeamBound({{"four", four}, {"eight", eight}});
        FAIL() << "a candidate with other taps was accepted";
    } catch (const ProbeError& e) {
        EXPECT_NE(std::string(e.what()).find("eight: not the shape of four"), std::string::npos) << e.what();
    }
}

TEST(TableMix, EachLevelFiltersAsItsSource) {
    // Level m of the mix from source m: 4, 8 and 16 taps at 16^2; the mix holds 16 and pads the rest.
    const TapTable four = lobeTable(16, 4, 4, TableForm::quadratic);
    const TapTable eight = lobeTable(16, 4, 8, TableForm::quadratic);
    const TapTable sixteen = lobeTable(16, 4, 16, TableForm::quadratic);
    const std::vector<MixSource> perLevel{{"four", four}, {"eight", eight}, {"sixteen", sixteen}, {"four", four}};
    const TapTable mixed = mixTables(perLevel);
    EXPECT_EQ(mixed.taps, 16);
    const CubeImage sky = skyProbe(16);
    const std::vector<DownsampleOperator> ops = pyramidOperators(16, mixed.pyramid);
    for (int m = 1; m < 4; ++m) { // level 0 is a copy
        const TapTable& source = perLevel[m].table;
        EXPECT_EQ(tapsInUse(mixed, m), source.taps) << "level " << m;
        // Bit for bit: the padding is skipped, so the same taps are summed in the same order.
        EXPECT_EQ(tableFilter(sky, mixed)[m].rgb, tableFilter(sky, source)[m].rgb) << "level " << m;
        EXPECT_EQ(tableImpulseResponse(mixed, ops, m, {4, 3, 5}), tableImpulseResponse(source, ops, m, {4, 3, 5})) << "level " << m;
    }
    EXPECT_NE(mixed.solver.find("1: eight (8 taps)"), std::string::npos) << mixed.solver;
}

TEST(TableMix, MeasuresALevelFromAnotherBudgetOnTheMixsBudget) {
    // Level 1 from a source fitted on a smaller stratified budget: every level's stratified record
    // must be what probefit eval measures on the mix's budget (the first source's).
    TapTable four = lobeTable(16, 3, 4, TableForm::quadratic);
    TapTable eight = lobeTable(16, 3, 8, TableForm::quadratic);
    eight.stratifiedBudget = 64;
    for (TapTable* t : {&four, &eight})
        for (int m = 0; m < t->levelCount; ++m) t->levels[m].stratified = evaluateLevel(*t, m, TexelSet::stratified).error;
    TapTable eightOnFours = eight;
    eightOnFours.stratifiedBudget = four.stratifiedBudget;
    ASSERT_GT(std::abs(eight.levels[1].stratified.mean - evaluateLevel(eightOnFours, 1, TexelSet::stratified).error.mean), 1e-4);
    const TapTable mixed = mixTables({{"four", four}, {"eight", eight}, {"four", four}});
    EXPECT_EQ(mixed.stratifiedBudget, four.stratifiedBudget);
    for (int m = 0; m < mixed.levelCount; ++m)
        EXPECT_NEAR(mixed.levels[m].stratified.mean, evaluateLevel(mixed, m, TexelSet::stratified).error.mean, 1e-9) << "level " << m;
}

TEST(TableMix, PaddingIsHarmlessWhereNotSkipped) {
    // A consumer that evaluates every tap of the published layout reads the padding as zero weight
    // along R: a finite direction, so nothing turns into NaN.
    const TapTable mixed =
        mixTables({{"four", lobeTable(16, 2, 4, TableForm::constant)}, {"eight", lobeTable(16, 2, 8, TableForm::constant)}});
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int t = 4; t < 8; ++t) {
            const double* c = &mixed.levels[0].coefficients[mixed.offset(frame, t)];
            EXPECT_EQ(c[tapDirZ], 1.0);
            EXPECT_EQ(c[tapWeight], 0.0);
        }
}

TEST(TableMix, RefusesTheWrongCountAndOtherShapes) {
    const TapTable quad = lobeTable(16, 2, 4, TableForm::quadratic);
    const TapTable constant = lobeTable(16, 2, 4, TableForm::constant);
    const auto refusal = [](const std::vector<MixSource>& perLevel) {
        try {
            mixTables(perLevel);
        } catch (const ProbeError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(refusal({{"a", quad}}).find("1 source tables for 2 output levels"), std::string::npos);
    EXPECT_NE(refusal({{"a", quad}, {"b", constant}}).find("b: not the shape of a"), std::string::npos);
}

TEST(FisLevelSamples, TheMixAndItsChecks) {
    EXPECT_EQ(mixedLevelSamples(16, 7), (std::vector<int>{16, 16, 64, 256, 256, 256, 256}));
    EXPECT_EQ(mixedLevelSamples(128, 5), (std::vector<int>{128, 128, 512, 1024, 1024}));
    EXPECT_EQ(mixedLevelSamples(2048, 2), (std::vector<int>{2048, 2048}));
    FisSettings s;
    s.levelSamples = {1, 2};
    EXPECT_THROW(validateSampleCounts(s, 3), ProbeError);
    s.levelSamples = {1, 0, 2};
    EXPECT_THROW(validateSampleCounts(s, 3), ProbeError);
    s.levelSamples = {1, 5, 2};
    EXPECT_NO_THROW(validateSampleCounts(s, 3));
    // Each level as uniform FIS with that level's count.
    const TapGenerator mixed = fisTapGenerator(16, 3, RoughnessMapping::gltf, s);
    std::vector<Tap> a, b;
    for (int m = 1; m < 3; ++m) {
        mixed(m, {2, 5, 1}, a);
        fisTapGenerator(16, 3, RoughnessMapping::gltf, FisSettings{s.levelSamples[m], 0.0, {}, {}, FisMap::cube})(m, {2, 5, 1}, b);
        ASSERT_EQ(a.size(), b.size()) << "level " << m;
        for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k].direction, b[k].direction);
    }
}

} // namespace
} // namespace probefit
