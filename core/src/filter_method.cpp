#include "probe/filter_method.h"

#include <fmt/format.h>

#include "probe/error.h"

namespace probe {

std::string_view methodKindName(MethodKind kind) {
    switch (kind) {
    case MethodKind::table: return "table";
    case MethodKind::fis: return "fis";
    case MethodKind::reference: return "reference";
    }
    return "reference";
}

MethodKind parseMethodKind(std::string_view name) {
    for (MethodKind kind : {MethodKind::table, MethodKind::fis, MethodKind::reference})
        if (methodKindName(kind) == name) return kind;
    throw ParameterError("method.kind", fmt::format("{}: expected table, fis or reference", name));
}

void validateMethod(const FilterMethod& method, int faceSize, int levelCount, const RoughnessMapping& mapping) {
    validateMappingLevels(mapping, levelCount);
    switch (method.kind) {
    case MethodKind::table: {
        if (!method.table) throw ParameterError("method.table", "missing: the table method needs a tap table");
        const TapTable& table = *method.table;
        validateTable(table, "tap table");
        std::string reasons;
        const auto add = [&](const std::string& reason) { reasons += (reasons.empty() ? "" : "; ") + reason; };
        if (table.faceSize != faceSize) add(fmt::format("it is for face size {}, not {}", table.faceSize, faceSize));
        if (table.levelCount != levelCount) add(fmt::format("it has {} levels, not {}", table.levelCount, levelCount));
        if (table.mapping != mapping)
            add(fmt::format("it is for the {} roughness mapping, not {}", describeRoughnessMapping(table.mapping),
                            describeRoughnessMapping(mapping)));
        if (!reasons.empty()) throw ParameterError("method.table", fmt::format("does not fit: {}", reasons));
        break;
    }
    case MethodKind::fis: validateSampleCounts(method.fis, levelCount); break;
    case MethodKind::reference: break;
    }
    if (method.kind == MethodKind::table && method.table->lobe != method.lobe)
        throw ParameterError(
            "method.lobe", fmt::format("{}: the tap table is fitted for the {} lobe", lobeName(method.lobe), lobeName(method.table->lobe)));
    if (method.lobe == Lobe::charlie && method.kind == MethodKind::fis && method.fis.map == FisMap::paraboloid)
        throw ParameterError("method.lobe", "charlie: FIS on the dual-paraboloid map is GGX's alone; use fis on the cube pyramid");
}

} // namespace probe
