#include "command_line.h"

#include <string>

#include <fmt/format.h>

#include "probe/error.h"

namespace probefilter {

namespace {

std::string gInvocation;

// `argument` as a POSIX shell reads it back: as it is where it holds only safe characters, else in
// single quotes.
std::string shellQuoted(std::string_view argument) {
    const bool safe = !argument.empty() && argument.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                                                      "0123456789_-+=./:,@%^") == std::string_view::npos;
    if (safe) return std::string(argument);
    std::string quoted = "'";
    for (const char c : argument) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

// Every value an option or argument takes is given and UTF-8 (probe::commandLineValueProblem).
void refuseBadValues(CLI::App& app) {
    const CLI::Validator check([](const std::string& value) { return probe::commandLineValueProblem(value); }, "", "VALUE");
    for (CLI::Option* option : app.get_options())
        if (option->get_expected_min() > 0) option->check(check);
    for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) refuseBadValues(*command);
}

} // namespace

const std::string& invocation() { return gInvocation; }

int runCommandLine(CLI::App& app, const char* tool, int argc, char** argv) {
    gInvocation = tool;
    for (int a = 1; a < argc; ++a) gInvocation += " " + shellQuoted(argv[a]);
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
