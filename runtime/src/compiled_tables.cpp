// The tap tables of tables/*.json, embedded at configure time (runtime/CMakeLists.txt writes
// compiled_tables.inc) and parsed once by probecore's table reader.
#include <string_view>
#include <utility>

#include "probe/runtime.h"
#include "probe/table_io.h"

namespace probe::gpu {

namespace {

struct EmbeddedTable {
    std::string_view name;
    std::string_view json;
};

using namespace std::string_view_literals;

constexpr EmbeddedTable kEmbedded[] = {
#include "compiled_tables.inc"
    {""sv, ""sv}, // end
};

} // namespace

const std::vector<CompiledTable>& compiledTables() {
    static const std::vector<CompiledTable> tables = [] {
        std::vector<CompiledTable> list;
        for (const EmbeddedTable& e : kEmbedded)
            if (!e.name.empty())
                list.push_back({std::string(e.name), tableFromJson(e.json, std::string("tables/") + std::string(e.name) + ".json")});
        return list;
    }();
    return tables;
}

const CompiledTable* findCompiledTable(int faceSize, int levelCount, RoughnessMapping mapping, const PyramidSettings& pyramid) {
    const CompiledTable* best = nullptr;
    for (const CompiledTable& c : compiledTables()) {
        const TapTable& t = c.table;
        if (t.baseSize != faceSize || t.levelCount != levelCount || t.mapping != mapping || !(t.pyramid == pyramid)) continue;
        if (t.taps == 8 && t.form == TableForm::quadratic) return &c;
        if (!best) best = &c;
    }
    return best;
}

} // namespace probe::gpu
