#include "evaluate.h"

#include <algorithm>
#include <array>
#include <limits>

#include <glm/common.hpp>

#include "probe/cube.h"
#include "probe/reference.h"

namespace probefit {

using namespace probe;

std::vector<WeightedTexel> levelTexels(const TapTable& table, int level, TexelSet set) {
    const int size = table.faceSize >> level;
    return set == TexelSet::all ? allTexels(size) : stratifiedTexels(size, table.stratifiedBudget);
}

namespace {

// A texel's class under the cube's 48 symmetries: its cube point's absolute coordinates, sorted
// (exact, since texel centres lie on a grid that the symmetries map onto itself).
using SymmetryKey = std::array<double, 3>;
SymmetryKey symmetryKey(const Texel& t, int size) {
    const glm::dvec3 p = glm::abs(texelCubePoint(t, size));
    SymmetryKey key{p.x, p.y, p.z};
    std::ranges::sort(key);
    return key;
}

// The distinct classes of `texels` of a level of face size `size`, sorted.
std::vector<SymmetryKey> symmetryClasses(const std::vector<WeightedTexel>& texels, int size) {
    std::vector<SymmetryKey> keys;
    keys.reserve(texels.size());
    for (const WeightedTexel& t : texels) keys.push_back(symmetryKey(t.texel, size));
    std::ranges::sort(keys);
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return keys;
}

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

std::size_t symmetryClassCount(int size) { return symmetryClasses(allTexels(size), size).size(); }

std::vector<OutputTexel> measuredTexels(const CubeGeometry& geometry, int level, const LevelLobe& lobe,
                                        const std::vector<WeightedTexel>& texels) {
    const int size = geometry.size >> level;
    // The kernels' normalizations, the one pass over every base texel: once per class, since the
    // base texels are symmetric too (probe::ReferenceLobe). The rest reads only where the taps reach.
    const std::vector<SymmetryKey> classes = symmetryClasses(texels, size);
    std::vector<double> normalizations(classes.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (std::size_t c = 0; c < classes.size(); ++c)
        normalizations[c] = ReferenceLobe(glm::dvec3(classes[c][0], classes[c][1], classes[c][2]), geometry, lobe).normalization();
    std::vector<OutputTexel> measured(texels.size());
#pragma omp parallel for schedule(dynamic, 8)
    for (std::size_t n = 0; n < texels.size(); ++n) {
        const auto c = std::ranges::lower_bound(classes, symmetryKey(texels[n].texel, size)) - classes.begin();
        measured[n] = makeMeasuredTexel(texels[n], geometry, level, lobe, normalizations[static_cast<std::size_t>(c)]);
    }
    return measured;
}

LevelEvaluation evaluateLevel(const TapTable& table, int level, TexelSet set) {
    const LevelLobe lobe = tableLevelLobe(table, level);
    if (lobe.alpha <= 0.0) return {};
    const ImpulseModel model(table.faceSize, table.pyramid, table.taps, table.form);
    const CubeGeometry geometry(table.faceSize);
    return evaluatePrepared(model, levelBlocks(table, level).data(), measuredTexels(geometry, level, lobe, levelTexels(table, level, set)));
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

void recordEvaluation(TableLevel& level, TexelSet set, const LevelEvaluation& evaluation) {
    const bool otherRecorded = (set == TexelSet::all ? level.stratified.mean : level.all.mean) >= 0.0;
    (set == TexelSet::all ? level.all : level.stratified) = evaluation.error;
    level.minWeightSum = otherRecorded ? std::min(level.minWeightSum, evaluation.minWeightSum) : evaluation.minWeightSum;
}

void restratifyLevel(TapTable& table, int level) {
    recordEvaluation(table.levels[level], TexelSet::stratified, evaluateLevel(table, level, TexelSet::stratified));
}

} // namespace probefit
