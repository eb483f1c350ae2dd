// The exception types for bad input: the message names the file (or parameter) and the problem.
#pragma once

#include <stdexcept>
#include <string>

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

} // namespace probe
