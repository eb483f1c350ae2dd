// What probefilter and probebench share around their subcommands: values checked the same way, and
// every refusal as one line with exit code 2.
#pragma once

#include <CLI/CLI.hpp>

namespace probefilter {

// Parses the command line and runs the chosen subcommand: 0 on success; on bad input or failure one
// line "TOOL: error: ..." on stderr (a library parameter named by its flag) and 2.
int runCommandLine(CLI::App& app, const char* tool, int argc, char** argv);

// The command line runCommandLine was given, as a shell takes it back (arguments quoted where they
// need it): what a report says wrote it.
const std::string& invocation();

} // namespace probefilter
