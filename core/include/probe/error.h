// The exception types for bad input: the message names the file (or parameter) and the problem.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace probe {

struct ProbeError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// A bad value of a library parameter: the message is "<parameter> <value>: <problem>", so that a
// front end can name its own option for the parameter (the command line's flag, a scene's field).
struct ParameterError : ProbeError {
    ParameterError(const std::string& name, const std::string& valueAndProblem)
        : ProbeError(name + " " + valueAndProblem), parameter(name) {}
    std::string parameter;
};

// The command-line flag that sets a library parameter (ParameterError::parameter: the name of the
// field in the library's settings, such as "method.fis.bias"), or empty where no flag does: the one
// table between the library's names and the tools' flags.
std::string_view parameterFlag(std::string_view parameter);
// The error's message with its parameter named by that flag where it has one ("--fis-bias 9: ...").
std::string messageWithFlag(const ParameterError& e);

// `message` as one line: control characters (a newline in a file name or in a JSON key a message
// quotes) written as escapes, so that a refusal stays the one line it promises.
std::string oneLine(std::string_view message);

// What is wrong with a value given on a command line, or empty: an empty value is not taken as the
// default, and a value must be UTF-8, since reports and tables are JSON, which holds nothing else.
std::string commandLineValueProblem(std::string_view value);

// Writes `text` to stderr. A stderr that cannot be written (closed, a full disk) is ignored: the
// exit code still tells what happened.
void printToStderr(std::string_view text);

} // namespace probe
