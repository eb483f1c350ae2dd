#include "table_mix.h"

#include <algorithm>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "evaluate.h"
#include "probe/error.h"

namespace probefit {

using namespace probe;

namespace {

void checkMixable(const std::vector<MixSource>& perLevel) {
    if (perLevel.empty()) throw ProbeError("mix: no source tables");
    const MixSource& first = perLevel.front();
    if (static_cast<int>(perLevel.size()) != first.table.levelCount)
        throw ProbeError(fmt::format("mix: {} source tables for {} output levels ({} has {}): give one per level", perLevel.size(),
                                     first.table.levelCount, first.name, first.table.levelCount));
    for (const MixSource& s : perLevel) {
        const TapTable& t = s.table;
        if (t.faceSize != first.table.faceSize || t.levelCount != first.table.levelCount || t.form != first.table.form ||
            t.mapping != first.table.mapping || !(t.pyramid == first.table.pyramid))
            throw ProbeError(
                fmt::format("{}: not the shape of {} (size, levels, form, mapping and pyramid must agree)", s.name, first.name));
    }
}

// Level `level` of `source` in a table of `taps` >= source.taps per frame: the source's taps first,
// then taps of zero weight pointing along R (a valid direction, so that a filter that does not skip
// them still reads finite values).
std::vector<double> paddedLevel(const TapTable& source, int level, const TapTable& shape) {
    std::vector<double> coefficients(static_cast<std::size_t>(shape.coefficientsPerLevel()), 0.0);
    const int perParameter = coefficientCount(shape.form);
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int tap = 0; tap < shape.taps; ++tap) {
            double* to = &coefficients[shape.offset(frame, tap)];
            if (tap < source.taps) {
                const double* from = &source.levels[level].coefficients[source.offset(frame, tap)];
                std::copy(from, from + kTapParameterCount * perParameter, to);
            } else {
                to[tapDirZ * perParameter] = 1.0;
            }
        }
    return coefficients;
}

} // namespace

TapTable mixTables(const std::vector<MixSource>& perLevel) {
    checkMixable(perLevel);
    int taps = 0;
    for (const MixSource& s : perLevel) taps = std::max(taps, s.table.taps);
    const TapTable& first = perLevel.front().table;
    TapTable mixed = emptyTable(first.faceSize, first.levelCount, taps, first.form, first.mapping, first.pyramid);
    mixed.stratifiedBudget = first.stratifiedBudget;
    mixed.seamWeight = first.seamWeight;
    std::set<std::string> counted;
    std::vector<std::string> levels, sources;
    for (int m = 0; m < mixed.levelCount; ++m) {
        const MixSource& s = perLevel[m];
        TableLevel& level = mixed.levels[m];
        level = s.table.levels[m];
        level.coefficients = paddedLevel(s.table, m, mixed);
        // The mix keeps the first source's stratified budget.
        if (s.table.stratifiedBudget != mixed.stratifiedBudget) restratifyLevel(mixed, m);
        // The seam weight is recorded only where every level was fitted with the same one.
        if (s.table.seamWeight != mixed.seamWeight) mixed.seamWeight = 0.0;
        levels.push_back(fmt::format("{}: {} ({} taps)", m, s.name, s.table.taps));
        if (counted.insert(s.name).second) {
            mixed.fitSeconds += s.table.fitSeconds;
            sources.push_back(fmt::format("[{}: {}]", s.name, s.table.solver));
        }
    }
    mixed.solver = fmt::format("probefit mix: level m from the m-th source, padded to {} taps with taps of zero weight (level: source) "
                               "{}; the sources: {}",
                               taps, fmt::join(levels, ", "), fmt::join(sources, " "));
    validateTable(mixed, "mixed table");
    return mixed;
}

} // namespace probefit
