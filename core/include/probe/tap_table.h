// The tap table of docs/design.md (the optimizer's output, the runtime's input), in memory.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "probe/error_measures.h"
#include "probe/frame.h"
#include "probe/lobe.h"
#include "probe/pyramid.h"
#include "probe/roughness.h"

namespace probe {

// quadratic: P = c0 + c1 theta^2 + c2 phi^2; constant: P = c0.
enum class TableForm { constant, quadratic };
TableForm parseTableForm(std::string_view name); // "const" or "quad"; throws ProbeError naming the value
std::string_view tableFormName(TableForm form);  // the name parseTableForm reads
// Coefficients per tap parameter.
inline int coefficientCount(TableForm form) { return form == TableForm::quadratic ? 3 : 1; }

// One output level: the coefficients and what the fit achieved.
struct TableLevel {
    // Coefficient c of parameter p of tap t in frame f at
    // ((f * taps + t) * kTapParameterCount + p) * coefficientCount + c.
    std::vector<double> coefficients;
    ImpulseError stratified;   // impulse L1 over the stratified output texels (what the fit sees)
    ImpulseError all;          // over every output texel of all six faces; mean < 0 where not measured
    double minWeightSum = 0.0; // smallest sum of tap weights over the output texels measured
    // The hand-off: > 0 where FIS with this many samples per texel (bias 0, on the table's pyramid)
    // filters the level better at no more time (probebench sweep's levels.md), and filters it in
    // the table's place; 0 where the table's taps do. The coefficients stay: they are the fit's.
    int fisSamples = 0;
};

struct TapTable {
    int faceSize = 0;   // S_0
    int levelCount = 0; // M output levels (roughnesses)
    int taps = 0;       // N per frame, a multiple of 4
    TableForm form = TableForm::quadratic;
    RoughnessMapping mapping = RoughnessMapping::gltf;
    Lobe lobe = Lobe::ggx; // the lobe its levels are fitted to
    PyramidSettings pyramid;
    std::string solver;         // the solver settings, free text
    int stratifiedBudget = 512; // texel budget per level of the stratified set (stratified_texels.h)
    double fitSeconds = 0.0;
    double seamWeight = 0.0;        // the fit's seam term weight (0: fitted on the L1 alone)
    std::vector<TableLevel> levels; // levelCount entries

    int coefficientsPerLevel() const { return kFrameCount * taps * kTapParameterCount * coefficientCount(form); }
    std::size_t offset(int frame, int tap, int parameter = 0) const {
        return (static_cast<std::size_t>(frame * taps + tap) * kTapParameterCount + parameter) * coefficientCount(form);
    }
};

// A table with zero coefficients and unmeasured errors; checks the sizes (ProbeError otherwise).
TapTable emptyTable(int faceSize, int levelCount, int taps, TableForm form, const RoughnessMapping& mapping, PyramidSettings pyramid);

// Throws ProbeError("<what>: <problem>") unless sizes, level count, taps and coefficient counts agree,
// and each hand-off is 0 or, at a filtered level (alpha > 0), 1 to kMaxSamples (limits.h) samples.
void validateTable(const TapTable& table, std::string_view what);

// Throws ProbeError("<what>: <problem>") unless the values make a filter: every coefficient finite and
// at most kMaxTableCoefficient (limits.h) in magnitude; and at every output texel of every filtered
// level a positive tap weight sum that is not the near-cancellation of large weights (the filter
// divides by it), and a direction for each tap the GPU reads there (those in use, and the padding to
// a group of four). For tables from files; validateTable checks only the shape.
void validateTableValues(const TapTable& table, std::string_view what);

// The taps per frame that output level `level` uses: one past the last tap with a weight that is not
// zero for every (theta, phi) in any frame. A level that uses fewer taps than the table holds is
// padded with taps of zero weight (probefit mix); they add nothing, so the filters stop before them.
int tapsInUse(const TapTable& table, int level);

// The published layout of one level as floats: quad `vec4 coeffs[5][3][3N/4]` (parameter,
// coefficient, frame * N/4 + tap/4, tap % 4 in the vec4), const `vec4 coeffs[5][3N/4]`.
std::vector<float> publishedLevelLayout(const TapTable& table, int level);

// The columns of a generated header's kLevelFits (table_io.h), one row per level: the stratified
// texels' impulse L1 (mean, max, worst texel face, i, j), the same over every texel, the smallest
// weight sum. The runtime reads the compiled-in tables' fits from it.
inline constexpr int kLevelFitColumns = 11;

// Sets every level's coefficients from the published layout, level after level (ProbeError unless the
// count matches the table's shape).
void setPublishedLayout(TapTable& table, const std::vector<double>& values);

// The alpha output level m of the table is fitted at: its lobe's (lobeAlpha; a GGX 0 is a copy of
// the source).
inline double tableLevelAlpha(const TapTable& table, int level) {
    return lobeAlpha(table.lobe, levelAlpha(table.mapping, level, table.levelCount));
}
inline LevelLobe tableLevelLobe(const TapTable& table, int level) { return {table.lobe, tableLevelAlpha(table, level)}; }

} // namespace probe
