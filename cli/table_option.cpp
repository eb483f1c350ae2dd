#include "table_option.h"

#include <cctype>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "probe/committed_tables.h"
#include "probe/error.h"
#include "probe/input_file.h"
#include "probe/limits.h"
#include "probe/runtime.h"
#include "probe/table_io.h"

namespace probefilter {

namespace {

bool looksLikeJson(const std::filesystem::path& path) {
    std::ifstream in(path);
    char c = 0;
    while (in.get(c))
        if (!std::isspace(static_cast<unsigned char>(c))) return c == '{';
    return false;
}

} // namespace

probe::TapTable tableOption(const std::string& table, const PublishedLayout& published) {
    for (const probe::gpu::CompiledTable& c : probe::gpu::compiledTables())
        if (c.name == table) return c.table;
    std::filesystem::path path(table);
    std::error_code ec;
    // A plain name that is no file here: the committed table of that name.
    if (!std::filesystem::exists(path, ec) && path.filename() == path && !table.empty() && table[0] != '.') {
        const std::filesystem::path committed = probe::committedTablesFolder() / (table + ".json");
        if (std::filesystem::is_regular_file(committed, ec)) return probe::readTable(committed);
    }
    if (table.empty() || !std::filesystem::exists(path, ec))
        throw probe::ProbeError(fmt::format("--table {}: no such file, no compiled-in table and no table in {} of that name", table,
                                            probe::committedTablesFolder().string()));
    probe::checkInputFile(path, probe::kMaxTextFileBytes);
    if (looksLikeJson(path)) return probe::readTable(path);
    if (published.taps <= 0 || published.form.empty())
        throw probe::ProbeError(
            fmt::format("--table {}: a table in the published text layout needs --table-taps N and --table-form const|quad", table));
    return probe::importPublishedTable(path, published.faceSize, published.levelCount, published.taps,
                                       probe::parseTableForm(published.form), published.mapping, published.pyramid);
}

} // namespace probefilter
