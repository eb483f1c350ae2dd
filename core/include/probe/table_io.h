// Tap tables on disk: the project's own table file (JSON, with every input and the achieved
// errors), the published plain-text layout, and the generated C++ header and GLSL include.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "probe/tap_table.h"

namespace probe {

// The project's table file. Reading refuses (ProbeError naming the file and the problem) anything
// that is not a complete table of a consistent layout: truncated, wrong sizes, unknown names.
TapTable readTable(const std::filesystem::path& path);
std::string tableToJson(const TapTable& table);
TapTable tableFromJson(std::string_view text, const std::filesystem::path& path);

// A plain-text file of numbers (separated by white space or commas) holding every level in the
// published layout (publishedLevelLayout), level 0 first. The file does not say its shape, so the
// caller does; the count must match exactly. Errors are left unmeasured.
// Reads such a file as a table of the shape given; writes a table in that layout.
TapTable importPublishedTable(const std::filesystem::path& path, int faceSize, int levelCount, int taps, TableForm form,
                              const RoughnessMapping& mapping, PyramidSettings pyramid);
void writePublishedTable(const std::filesystem::path& path, const TapTable& table);

// The inputs, solver settings, run time and per-level errors, one per line, for generated comments and logs.
std::vector<std::string> tableSummary(const TapTable& table);

// Generated sources: a C++ header (constants in namespace probe_tables::<name>: the table's shape,
// solver and fit, kTapGroups and kCoefficients; the runtime compiles tables in from these) and a GLSL
// include (PROBE_TABLE_* defines, `vec4 probeTableCoeffs[]` and `int probeTableTapGroups[]`,
// read-only globals), both in the published layout, level after level, opening with
// tableSummary as a comment. `name` must be a C identifier.
std::string tableCppHeader(const TapTable& table, std::string_view name);
std::string tableGlslInclude(const TapTable& table, std::string_view name);

} // namespace probe
