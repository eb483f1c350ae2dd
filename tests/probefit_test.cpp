// The optimizer's objective is the shared model: its L1 equals the one computed from probecore's
// impulse response and reference kernel, and its gradient matches finite differences.
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "evaluate.h"
#include "impulse_model.h"
#include "initial_layout.h"
#include "probe/reference.h"
#include "probe/table_filter.h"

namespace probefit {
namespace {

using namespace probe;

TapTable lobeTable(int baseSize, int levelCount, int taps, TableForm form) {
    TapTable table = emptyTable(baseSize, levelCount, taps, form, RoughnessMapping::gltf, {});
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> jitter(-0.05, 0.05);
    for (int m = 1; m < levelCount; ++m) {
        lobeLayout(table, m, tableLevelAlpha(table, m));
        for (double& c : table.levels[m].coefficients) c += jitter(rng); // break symmetries, quad terms non-zero
    }
    return table;
}

TEST(ImpulseModel, EqualsTheSharedModel) {
    for (TableForm form : {TableForm::constant, TableForm::quadratic}) {
        const TapTable table = lobeTable(16, 4, 4, form);
        const ImpulseModel model(16, table.pyramid, table.taps, table.form);
        const std::vector<DownsampleOperator> ops = pyramidOperators(16, table.pyramid);
        ImpulseModel::Workspace ws = model.workspace();
        for (int m = 1; m < 4; ++m) {
            const double alpha = tableLevelAlpha(table, m);
            const std::vector<OutputTexel> texels = prepareTexels(stratifiedTexels(16 >> m, 40), 16, m, alpha);
            for (const OutputTexel& t : texels) {
                const double expected = impulseL1(tableImpulseResponse(table, ops, m, t.texel),
                                                  referenceKernel(t.cubeVector, 16, alpha));
                EXPECT_NEAR(model.evaluate(levelBlocks(table, m).data(), t, ws).error, expected, 1e-6);
            }
        }
    }
}

TEST(ImpulseModel, GradientMatchesFiniteDifferences) {
    TapTable table = lobeTable(16, 4, 4, TableForm::quadratic);
    const int m = 2;
    const ImpulseModel model(16, table.pyramid, table.taps, table.form);
    ImpulseModel::Workspace ws = model.workspace();
    const std::vector<OutputTexel> texels = prepareTexels(stratifiedTexels(16 >> m, 12), 16, m, tableLevelAlpha(table, m));
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
            const double fd = (plus.error - minus.error) / (2 * h);
            ++checked;
            // |.| and texel boundaries make e piecewise smooth; most coefficients must agree closely.
            if (std::abs(fd - gradient[q]) <= 1e-4 + 1e-3 * std::abs(fd)) ++agreeing;
            EXPECT_NEAR((plus.weightSum - minus.weightSum) / (2 * h), weightGradient[q], 1e-6);
        }
    }
    EXPECT_GE(agreeing, checked * 9 / 10) << agreeing << " of " << checked;
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

} // namespace
} // namespace probefit
