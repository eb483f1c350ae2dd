#include "probe/tap_table.h"

#include <fmt/format.h>

#include "probe/error.h"

namespace probe {

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
    if (taps < 4 || taps % 4 != 0) throw ProbeError(fmt::format("tap count {} is not a positive multiple of 4", taps));
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
    if (table.taps < 4 || table.taps % 4 != 0)
        throw ProbeError(fmt::format("{}: tap count {} is not a positive multiple of 4", what, table.taps));
    if (table.levels.size() != static_cast<std::size_t>(table.levelCount))
        throw ProbeError(fmt::format("{}: {} levels of coefficients for a level count of {}", what, table.levels.size(), table.levelCount));
    for (std::size_t m = 0; m < table.levels.size(); ++m)
        if (table.levels[m].coefficients.size() != static_cast<std::size_t>(table.coefficientsPerLevel()))
            throw ProbeError(fmt::format("{}: level {} has {} coefficients, expected {} ({} taps x 3 frames x 5 x {})", what, m,
                                         table.levels[m].coefficients.size(), table.coefficientsPerLevel(), table.taps,
                                         coefficientCount(table.form)));
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
