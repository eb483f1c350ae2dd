#include "probe/limits.h"

#include <fmt/format.h>

#include "probe/error.h"

namespace probe {

void checkRepeat(int repeat) {
    if (repeat < 1 || repeat > kMaxRepeat) throw ParameterError("repeat", fmt::format("{}: must be 1 to {}", repeat, kMaxRepeat));
}

} // namespace probe
