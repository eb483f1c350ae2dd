// The probefilter subcommands: each registers its options and runs when chosen.
#pragma once

#include <CLI/CLI.hpp>

namespace probefilter {

void addReferenceCommand(CLI::App& app);
void addSynthCommand(CLI::App& app);
void addFilterCommand(CLI::App& app);
void addPlanCommand(CLI::App& app);
void addRunCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addSweepCommand(CLI::App& app);

} // namespace probefilter
