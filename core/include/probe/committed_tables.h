// Where the tools find the committed tap tables (tables/*.json) by name.
#pragma once

#include <filesystem>

namespace probe {

// The committed tables' folder: installed beside the running executable
// (bin/../share/probefilter/tables), else the source tree's tables/ the tools were built from.
std::filesystem::path committedTablesFolder();

} // namespace probe
