#include "command_line.h"

#include <string>

#include <fmt/format.h>

#include "probe/error.h"

namespace probefilter {

namespace {

// Every value an option or argument takes is given and UTF-8 (probe::commandLineValueProblem).
void refuseBadValues(CLI::App& app) {
    const CLI::Validator check([](const std::string& value) { return probe::commandLineValueProblem(value); }, "", "VALUE");
    for (CLI::Option* option : app.get_options())
        if (option->get_expected_min() > 0) option->check(check);
    for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) refuseBadValues(*command);
}

} // namespace

int runCommandLine(CLI::App& app, const char* tool, int argc, char** argv) {
    // The one line of a refusal; stderr that cannot be written is ignored (the exit code tells).
    auto refuse = [tool](const std::string& message) {
        probe::printToStderr(fmt::format("{}: error: {}\n", tool, probe::oneLine(message)));
        return 2;
    };
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
        return refuse(probe::messageWithFlag(e));
    } catch (const probe::ProbeError& e) {
        return refuse(e.what());
    } catch (const std::exception& e) {
        return refuse(e.what());
    }
    return 0;
}

} // namespace probefilter
