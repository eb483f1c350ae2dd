#include "evaluate.h"

#include <algorithm>
#include <limits>

#include "probe/reference.h"

namespace probefit {

using namespace probe;

std::vector<WeightedTexel> levelTexels(const TapTable& table, int level, TexelSet set) {
    const int size = table.baseSize >> level;
    return set == TexelSet::all ? allTexels(size) : stratifiedTexels(size, table.stratifiedBudget);
}

namespace {

// Errors of texels in a fixed order, so the worst texel and the sums do not depend on threads.
LevelEvaluation combine(const std::vector<WeightedTexel>& texels, const std::vector<ImpulseModel::Result>& results) {
    ImpulseErrorAccumulator accumulator;
    double minWeightSum = std::numeric_limits<double>::max(), tail = 0.0, total = 0.0;
    for (std::size_t n = 0; n < texels.size(); ++n) {
        accumulator.add(texels[n].texel, texels[n].weight, results[n].error);
        minWeightSum = std::min(minWeightSum, results[n].weightSum);
        tail += texels[n].weight * results[n].tail;
        total += texels[n].weight;
    }
    return {accumulator.result(), minWeightSum, total > 0.0 ? tail / total : 0.0};
}

} // namespace

LevelEvaluation evaluateLevel(const TapTable& table, int level, TexelSet set) {
    const double alpha = tableLevelAlpha(table, level);
    if (alpha <= 0.0) return {};
    const std::vector<WeightedTexel> texels = levelTexels(table, level, set);
    const ImpulseModel model(table.baseSize, table.pyramid, table.taps, table.form);
    const CubeGeometry geometry(table.baseSize);
    const std::vector<const double*> blocks = levelBlocks(table, level);
    std::vector<ImpulseModel::Result> results(texels.size());
#pragma omp parallel
    {
        ImpulseModel::Workspace ws = model.workspace();
#pragma omp for schedule(dynamic, 8)
        for (std::size_t n = 0; n < texels.size(); ++n)
            results[n] = model.evaluate(blocks.data(), makeOutputTexel(texels[n], geometry, level, alpha), ws);
    }
    return combine(texels, results);
}

LevelEvaluation evaluatePrepared(const ImpulseModel& model, const double* const* blocks, const std::vector<OutputTexel>& texels) {
    std::vector<ImpulseModel::Result> results(texels.size());
    std::vector<WeightedTexel> weighted(texels.size());
#pragma omp parallel
    {
        ImpulseModel::Workspace ws = model.workspace();
#pragma omp for schedule(dynamic, 4)
        for (std::size_t n = 0; n < texels.size(); ++n) {
            results[n] = model.evaluate(blocks, texels[n], ws);
            weighted[n] = {texels[n].texel, texels[n].weight};
        }
    }
    return combine(weighted, results);
}

void restratifyLevel(TapTable& table, int level) {
    TableLevel& kept = table.levels[level];
    const LevelEvaluation stratified = evaluateLevel(table, level, TexelSet::stratified);
    kept.stratified = stratified.error;
    kept.minWeightSum = kept.all.mean >= 0.0 ? std::min(kept.minWeightSum, stratified.minWeightSum) : stratified.minWeightSum;
}

} // namespace probefit
