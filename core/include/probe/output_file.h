// Output files: every file probefilter and probefit write goes through writeFile, which writes it
// whole or fails, so that a full disk or a file-size limit becomes an error naming the file rather
// than a short file in an output that is then committed.
#pragma once

#include <filesystem>
#include <string_view>

namespace probe {

// Writes `bytes` to `path` (replacing it). Throws ProbeError naming the path and the system's reason
// when any of it cannot be written, closing included (a buffered write's error can surface there).
void writeFile(const std::filesystem::path& path, std::string_view bytes);

// Writes all of `bytes` to the open file `fd`, through short and interrupted writes: 0, or the errno
// of the failure (ENOSPC for a write that makes no progress). For writers that own their file, as an
// EXR stream does.
int writeAll(int fd, std::string_view bytes);

} // namespace probe
