#include "probe/tap_table.h"

#include <cmath>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/limits.h"
#include "probe/stratified_texels.h"
#include "probe/table_filter.h"

namespace probe {

namespace {

// A weight sum below this fraction of the weights' magnitude is cancellation, not a filter.
constexpr double kMinWeightSumRatio = 1e-3;
// Output texels per level at which the weights are checked (a fit's default stratified budget).
constexpr int kCheckedTexels = 512;

} // namespace

TableForm parseTableForm(std::string_view name) {
    if (name == "quad") return TableForm::quadratic;
    if (name == "const") return TableForm::constant;
    throw ProbeError(fmt::format("unknown table form '{}' (expected const or quad)", name));
}

std::string_view tableFormName(TableForm form) { return form == TableForm::quadratic ? "quad" : "const"; }

TapTable emptyTable(int baseSize, int levelCount, int taps, TableForm form, RoughnessMapping mapping, PyramidSettings pyramid) {
    TapTable table;
    table.baseSize = baseSize;
    table.levelCount = levelCount;
    table.taps = taps;
    table.form = form;
    table.mapping = mapping;
    table.pyramid = pyramid;
    validateSizeAndLevels(baseSize, levelCount);
    if (taps < 4 || taps % 4 != 0 || taps > kMaxTaps)
        throw ProbeError(fmt::format("tap count {} is not a multiple of 4 from 4 to {}", taps, kMaxTaps));
    table.levels.resize(static_cast<std::size_t>(levelCount));
    for (TableLevel& level : table.levels) {
        level.coefficients.assign(static_cast<std::size_t>(table.coefficientsPerLevel()), 0.0);
        level.stratified.mean = -1.0;
        level.all.mean = -1.0;
    }
    return table;
}

void validateTable(const TapTable& table, std::string_view what) {
    try {
        validateSizeAndLevels(table.baseSize, table.levelCount);
    } catch (const ProbeError& e) {
        throw ProbeError(fmt::format("{}: {}", what, e.what()));
    }
    if (table.taps < 4 || table.taps % 4 != 0 || table.taps > kMaxTaps)
        throw ProbeError(fmt::format("{}: tap count {} is not a multiple of 4 from 4 to {}", what, table.taps, kMaxTaps));
    if (table.levels.size() != static_cast<std::size_t>(table.levelCount))
        throw ProbeError(fmt::format("{}: {} levels of coefficients for a level count of {}", what, table.levels.size(), table.levelCount));
    for (std::size_t m = 0; m < table.levels.size(); ++m)
        if (table.levels[m].coefficients.size() != static_cast<std::size_t>(table.coefficientsPerLevel()))
            throw ProbeError(fmt::format("{}: level {} has {} coefficients, expected {} ({} taps x 3 frames x 5 x {})", what, m,
                                         table.levels[m].coefficients.size(), table.coefficientsPerLevel(), table.taps,
                                         coefficientCount(table.form)));
}

void validateTableValues(const TapTable& table, std::string_view what) {
    validateTable(table, what);
    for (int m = 0; m < table.levelCount; ++m)
        for (std::size_t k = 0; k < table.levels[m].coefficients.size(); ++k) {
            const double c = table.levels[m].coefficients[k];
            if (!(std::abs(c) <= kMaxTableCoefficient))
                throw ProbeError(
                    fmt::format("{}: level {} coefficient {} is {}, not a finite number within +-{}", what, m, k, c, kMaxTableCoefficient));
        }
    std::vector<Tap> taps;
    for (int m = 0; m < table.levelCount; ++m) {
        if (tableLevelAlpha(table, m) <= 0.0) continue; // a copy: the taps are not used
        const int size = table.baseSize >> m, used = tapsInUse(table, m);
        for (const WeightedTexel& w : stratifiedTexels(size, kCheckedTexels)) {
            const Texel& t = w.texel;
            tableTaps(table, m, used, texelCubePoint(t, size), taps);
            double sum = 0.0, magnitude = 0.0;
            for (const Tap& tap : taps) {
                if (!std::isfinite(tap.direction.x + tap.direction.y + tap.direction.z + tap.level))
                    throw ProbeError(fmt::format("{}: level {} at texel (face {}, {}, {}): a tap has no direction (all its direction "
                                                 "coefficients are 0)",
                                                 what, m, t.face, t.i, t.j));
                sum += tap.weight;
                magnitude += std::abs(tap.weight);
            }
            if (!(sum > kMinWeightSumRatio * magnitude))
                throw ProbeError(
                    fmt::format("{}: level {} at texel (face {}, {}, {}): the tap weights sum to {:.3g} (of magnitude {:.3g}); "
                                "the filter needs a positive sum",
                                what, m, t.face, t.i, t.j, sum, magnitude));
        }
    }
}

int tapsInUse(const TapTable& table, int level) {
    const std::vector<double>& c = table.levels[level].coefficients;
    for (int tap = table.taps; tap > 0; --tap)
        for (int frame = 0; frame < kFrameCount; ++frame)
            for (int k = 0; k < coefficientCount(table.form); ++k)
                if (c[table.offset(frame, tap - 1, tapWeight) + k] != 0.0) return tap;
    return 0;
}

} // namespace probe
