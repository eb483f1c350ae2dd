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

constexpr EmbeddedTable kEmbedded[] = {
#include "compiled_tables.inc"
    {"", ""}, // end
};

} // namespace

const std::vector<CompiledTable>& compiledTables() {
    static const std::vector<CompiledTable> tables = [] {
        std::vector<CompiledTable> list;
        for (const EmbeddedTable& e : kEmbedded)
            if (!e.name.empty()) list.push_back({std::string(e.name), tableFromJson(e.json, std::string("tables/") + std::string(e.name) + ".json")});
        return list;
    }();
    return tables;
}

} // namespace probe::gpu
