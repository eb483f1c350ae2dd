#include "probe/tap_table.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/limits.h"
#include "probe/table_filter.h"

namespace probe {

namespace {

// A weight sum below this fraction of the weights' magnitude is cancellation, not a filter.
constexpr double kMinWeightSumRatio = 1e-3;
// A tap direction shorter than this fraction of its coefficients' size has no direction: the GPU's
// float rounding, a few 1e-7 of it, could turn it anywhere or cancel it to zero. (The committed
// tables' shortest are above 1e-5 of theirs.)
constexpr double kMinDirectionRatio = 1e-6;

// The size of tap `tap`'s direction coefficients in `frame` of `level`: the sum of their terms' lengths.
double directionScale(const TapTable& table, int level, int frame, int tap) {
    double scale = 0.0;
    for (int k = 0; k < coefficientCount(table.form); ++k) {
        glm::dvec3 term;
        for (int axis = 0; axis < 3; ++axis) term[axis] = table.levels[level].coefficients[table.offset(frame, tap, tapDirX + axis) + k];
        scale += glm::length(term);
    }
    return scale;
}

// Every output texel of level m, in each frame that counts there: each of the first `read` taps
// (the GPU evaluates taps in groups of four, so a level's padding up to its group too) has a
// direction that float rounding cannot cancel or turn, and the weights of the first `used`, frame
// weights included as tableTaps gives them, sum to a positive fraction of their magnitude.
void checkTexels(const TapTable& table, int m, int used, int read, std::string_view what) {
    const int n = coefficientCount(table.form), size = table.baseSize >> m;
    const std::vector<double>& c = table.levels[m].coefficients;
    std::vector<double> scales;
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int tap = 0; tap < read; ++tap) scales.push_back(directionScale(table, m, frame, tap));
    for (int face = 0; face < kFaceCount; ++face)
        for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i) {
                const glm::dvec3 d = texelCubePoint({face, i, j}, size);
                std::array<FrameSetup, kFrameCount> frames;
                double sum = 0.0, magnitude = 0.0;
                for (int frame = 0; frame < kFrameCount; ++frame) {
                    frames[frame] = frameSetup(d, frame);
                    if (frames[frame].weight <= 0.0) continue;
                    for (int tap = 0; tap < used; ++tap) {
                        const double w = tapPolynomial(&c[table.offset(frame, tap, tapWeight)], n, frames[frame]) * frames[frame].weight;
                        sum += w;
                        magnitude += std::abs(w);
                    }
                }
                if (!(sum > kMinWeightSumRatio * magnitude))
                    throw ProbeError(fmt::format("{}: level {} at texel (face {}, {}, {}): the tap weights sum to {:.3g} (of magnitude "
                                                 "{:.3g}); the filter needs a positive sum",
                                                 what, m, face, i, j, sum, magnitude));
                for (int frame = 0; frame < kFrameCount; ++frame) {
                    const FrameSetup& f = frames[frame];
                    if (f.weight <= 0.0) continue;
                    for (int tap = 0; tap < read; ++tap) {
                        const glm::dvec3 p(tapPolynomial(&c[table.offset(frame, tap, tapDirX)], n, f),
                                           tapPolynomial(&c[table.offset(frame, tap, tapDirY)], n, f),
                                           tapPolynomial(&c[table.offset(frame, tap, tapDirZ)], n, f));
                        const double scale = scales[std::size_t(frame * read + tap)];
                        if (!(glm::length(p) > kMinDirectionRatio * scale))
                            throw ProbeError(fmt::format("{}: level {} frame {} tap {} has no direction at texel (face {}, {}, {}) (its "
                                                         "direction coefficients {})",
                                                         what, m, frame, tap, face, i, j, scale == 0.0 ? "are all 0" : "cancel there"));
                    }
                }
            }
}

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
    for (int m = 0; m < table.levelCount; ++m) {
        if (tableLevelAlpha(table, m) <= 0.0) continue; // a copy: the taps are not used
        const int used = tapsInUse(table, m);
        checkTexels(table, m, used, std::min(table.taps, (std::max(used, 1) + 3) / 4 * 4), what);
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
