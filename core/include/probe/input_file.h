// Input files: what a path names is checked before it is opened, so that a folder, a FIFO or a
// device is refused by what it is, and a file is read only up to a stated size.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace probe {

// The size of the regular file at `path`. Throws ProbeError naming the path and what it is instead
// (missing, a folder, a FIFO, a device, a socket), or that it is over `maxBytes`.
std::uintmax_t checkInputFile(const std::filesystem::path& path, std::uintmax_t maxBytes);

// The whole of a regular file of at most kMaxTextFileBytes (limits.h), checked as checkInputFile does.
std::string readTextFile(const std::filesystem::path& path);

} // namespace probe
