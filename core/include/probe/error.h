// The one exception type for bad input: its message names the file (or option) and the problem.
#pragma once

#include <stdexcept>
#include <string>

namespace probe {

struct ProbeError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

} // namespace probe
