// The probebench subcommands: each registers its options and runs when chosen.
#pragma once

#include <CLI/CLI.hpp>

namespace probefilter {

void addCompareCommand(CLI::App& app); // the comparison sheet: reference, table and FIS-32 spheres
void addSweepCommand(CLI::App& app);   // error against time, every table and FIS setting
void addImpulseCommand(CLI::App& app); // impulse L1 of tables and FIS at any size, CPU alone

} // namespace probefilter
