// What probefit writes for an output prefix: PREFIX.json (the table file), PREFIX.h and PREFIX.glsl.
#pragma once

#include <filesystem>
#include <string>

#include "probe/tap_table.h"

namespace probefit {

// The C identifier of the generated sources: the prefix's file name, other characters as '_'.
std::string tableIdentifier(const std::filesystem::path& prefix);

// Throws ProbeError (naming --out) unless files can be created beside the prefix; creates nothing.
void checkWritable(const std::filesystem::path& prefix);

// Writes the three files under temporary names first, then renames them, so that a failure leaves none.
void writeTableOutputs(const std::filesystem::path& prefix, const probe::TapTable& table);

} // namespace probefit
