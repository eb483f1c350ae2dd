// The tap tables compiled into the runtime: the generated headers tables/<name>.h that
// PROBE_COMPILED_TABLES names (runtime/CMakeLists.txt writes compiled_tables.inc, which includes
// them and lists them in PROBE_COMPILED_TABLE_LIST). Nothing is parsed at run time.
#include <cstddef>
#include <span>
#include <string_view>

#include "probe/runtime.h"
#include "probe/tap_table.h"

#include "compiled_tables.inc"

namespace probe::gpu {

namespace {

// What a generated header holds, whatever its namespace.
struct HeaderTable {
    std::string_view name;
    int faceSize;
    int levelCount;
    int taps;
    std::string_view form;
    std::string_view mapping;
    std::string_view lobe;
    std::span<const double> levelRoughness;
    std::string_view pyramidKind;
    std::string_view pyramidWeighting;
    std::string_view solver;
    int stratifiedBudget;
    double fitSeconds;
    double seamWeight;
    std::span<const double[kLevelFitColumns]> levelFits;
    std::span<const int> fisSamples;
    std::span<const float> coefficients;
};

ImpulseError impulseError(const double* columns) {
    return {columns[0], columns[1], {static_cast<int>(columns[2]), static_cast<int>(columns[3]), static_cast<int>(columns[4])}};
}

CompiledTable compiledTable(const HeaderTable& h) {
    const std::string what = "tables/" + std::string(h.name) + ".h";
    const RoughnessMapping mapping = h.mapping == "custom" ? RoughnessMapping::custom({h.levelRoughness.begin(), h.levelRoughness.end()})
                                                           : parseRoughnessMapping(h.mapping);
    TapTable table = emptyTable(h.faceSize, h.levelCount, h.taps, parseTableForm(h.form), mapping,
                                {parsePyramidKind(h.pyramidKind), parsePyramidWeighting(h.pyramidWeighting)});
    table.lobe = parseLobe(h.lobe);
    table.solver = h.solver;
    table.stratifiedBudget = h.stratifiedBudget;
    table.fitSeconds = h.fitSeconds;
    table.seamWeight = h.seamWeight;
    const std::vector<double> coefficients(h.coefficients.begin(), h.coefficients.end());
    setPublishedLayout(table, coefficients);
    for (int m = 0; m < h.levelCount; ++m) {
        const double* fit = h.levelFits[static_cast<std::size_t>(m)];
        table.levels[m].stratified = impulseError(fit);
        table.levels[m].all = impulseError(fit + 5);
        table.levels[m].minWeightSum = fit[10];
        table.levels[m].fisSamples = h.fisSamples[static_cast<std::size_t>(m)];
    }
    validateTable(table, what);
    return {std::string(h.name), std::move(table)};
}

#define PROBE_HEADER_TABLE(name)                                                                                                           \
    HeaderTable{#name,                                                                                                                     \
                probe_tables::name::kFaceSize,                                                                                             \
                probe_tables::name::kLevelCount,                                                                                           \
                probe_tables::name::kTaps,                                                                                                 \
                probe_tables::name::kForm,                                                                                                 \
                probe_tables::name::kMapping,                                                                                              \
                probe_tables::name::kLobe,                                                                                                 \
                probe_tables::name::kLevelRoughness,                                                                                       \
                probe_tables::name::kPyramidKind,                                                                                          \
                probe_tables::name::kPyramidWeighting,                                                                                     \
                probe_tables::name::kSolver,                                                                                               \
                probe_tables::name::kStratifiedBudget,                                                                                     \
                probe_tables::name::kFitSeconds,                                                                                           \
                probe_tables::name::kSeamWeight,                                                                                           \
                probe_tables::name::kLevelFits,                                                                                            \
                probe_tables::name::kFisSamples,                                                                                           \
                probe_tables::name::kCoefficients},

const HeaderTable kHeaders[] = {PROBE_COMPILED_TABLE_LIST(PROBE_HEADER_TABLE)};

} // namespace

const std::vector<CompiledTable>& compiledTables() {
    static const std::vector<CompiledTable> tables = [] {
        std::vector<CompiledTable> list;
        for (const HeaderTable& h : kHeaders) list.push_back(compiledTable(h));
        return list;
    }();
    return tables;
}

const CompiledTable* findCompiledTable(int faceSize, int levelCount, const RoughnessMapping& mapping, const PyramidSettings& pyramid,
                                       Lobe lobe) {
    const CompiledTable* best = nullptr;
    for (const CompiledTable& c : compiledTables()) {
        const TapTable& t = c.table;
        if (t.faceSize != faceSize || t.levelCount != levelCount || t.mapping != mapping || !(t.pyramid == pyramid) || t.lobe != lobe)
            continue;
        if (t.taps == 8 && t.form == TableForm::quadratic) return &c;
        if (!best) best = &c;
    }
    return best;
}

} // namespace probe::gpu
