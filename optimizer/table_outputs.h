// What probefit writes for an output prefix: PREFIX.json (the table file), PREFIX.h and PREFIX.glsl.
#pragma once

#include <filesystem>
#include <string>

#include "probe/tap_table.h"

namespace probefit {

// The C identifier of the generated sources: the prefix's file name, other characters as '_'.
std::string tableIdentifier(const std::filesystem::path& prefix);

// Throws ProbeError (naming `flag`, the option that gave the prefix) unless the prefix's folder is
// writable and each of the three files is absent or a regular file (not a link, a folder, a device);
// creates nothing.
void checkWritable(const std::filesystem::path& prefix, const char* flag = "--out");

// Writes the three files as staged files (probe/staged_output.h: written beside, renamed over), so that
// a failure or an interrupt (probe/interrupt.h) leaves none of them; a failure names `flag`.
void writeTableOutputs(const std::filesystem::path& prefix, const probe::TapTable& table, const char* flag = "--out");

} // namespace probefit
