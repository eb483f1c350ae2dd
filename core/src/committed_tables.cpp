#include "probe/committed_tables.h"

namespace probe {

std::filesystem::path committedTablesFolder() {
    std::error_code error;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", error);
    const std::filesystem::path installed = exe.parent_path().parent_path() / "share" / "probefilter" / "tables";
    if (!error && std::filesystem::is_directory(installed, error)) return installed;
    return PROBE_SOURCE_TABLES_DIR;
}

} // namespace probe
