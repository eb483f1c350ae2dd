// probefilter: GGX-filtered reflection probes. Exit codes: 0 success, 2 bad input or failure.
#include <CLI/CLI.hpp>

#include "command_line.h"
#include "commands.h"
#include "probe/interrupt.h"

int main(int argc, char** argv) {
    probe::removeStagingOnInterrupt();
    CLI::App app{"probefilter: fast GGX filtering of reflection probes (Manson & Sloan 2016)"};
    app.require_subcommand(1);
    probefilter::addReferenceCommand(app);
    probefilter::addSynthCommand(app);
    probefilter::addFilterCommand(app);
    probefilter::addPlanCommand(app);
    probefilter::addRunCommand(app);
    return probefilter::runCommandLine(app, "probefilter", argc, argv);
}
