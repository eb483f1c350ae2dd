// probefilter: GGX-filtered reflection probes. Exit codes: 0 success, 2 bad input or failure.
#include <cstdio>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "commands.h"
#include "probe/error.h"
#include "probe/interrupt.h"

namespace {

// A library parameter's message with the command line's flag for it: "--repeat 0: must be ...".
std::string withFlag(const probe::ParameterError& e) {
    for (std::string_view flag :
         {"method", "table", "samples", "fis-bias", "fis-map", "repeat", "device", "sampling", "format", "pyramid-format", "roughness"})
        if (e.parameter == flag) return fmt::format("--{}", e.what());
    return e.what();
}

// Every value an option or argument takes is given and UTF-8 (probe::commandLineValueProblem).
void refuseBadValues(CLI::App& app) {
    const CLI::Validator check([](const std::string& value) { return probe::commandLineValueProblem(value); }, "", "VALUE");
    for (CLI::Option* option : app.get_options())
        if (option->get_expected_min() > 0) option->check(check);
    for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) refuseBadValues(*command);
}

// The one line of a refusal; stderr that cannot be written is ignored (the exit code tells).
int refuse(const std::string& message) {
    probe::printToStderr(fmt::format("probefilter: error: {}\n", probe::oneLine(message)));
    return 2;
}

} // namespace

int main(int argc, char** argv) {
    probe::removeStagingOnInterrupt();
    CLI::App app{"probefilter: fast GGX filtering of reflection probes (Manson & Sloan 2016)"};
    app.require_subcommand(1);
    probefilter::addReferenceCommand(app);
    probefilter::addSynthCommand(app);
    probefilter::addFilterCommand(app);
    probefilter::addPlanCommand(app);
    probefilter::addRunCommand(app);
    probefilter::addCompareCommand(app);
    probefilter::addSweepCommand(app);
    refuseBadValues(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        return refuse(e.what());
    } catch (const probe::ParameterError& e) {
        return refuse(withFlag(e));
    } catch (const probe::ProbeError& e) {
        return refuse(e.what());
    } catch (const std::exception& e) {
        return refuse(e.what());
    }
    return 0;
}
