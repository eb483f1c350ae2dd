// probebench: probefilter's measuring bench, the methods against the exact reference and each other.
// Exit codes: 0 success, 2 bad input or failure.
#include <CLI/CLI.hpp>

#include "bench_commands.h"
#include "command_line.h"
#include "probe/interrupt.h"

int main(int argc, char** argv) {
    probe::removeStagingOnInterrupt();
    CLI::App app{"probebench: probefilter's methods measured against the exact reference and each other"};
    app.require_subcommand(1);
    probefilter::addCompareCommand(app);
    probefilter::addSweepCommand(app);
    probefilter::addImpulseCommand(app);
    return probefilter::runCommandLine(app, "probebench", argc, argv);
}
