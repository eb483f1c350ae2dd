#include "probe/input_file.h"

#include <fstream>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/limits.h"

namespace fs = std::filesystem;

namespace probe {

namespace {

std::string_view kindName(fs::file_type type) {
    switch (type) {
    case fs::file_type::directory: return "a folder";
    case fs::file_type::fifo: return "a FIFO";
    case fs::file_type::socket: return "a socket";
    case fs::file_type::character:
    case fs::file_type::block: return "a device";
    default: return "not a regular file";
    }
}

} // namespace

std::uintmax_t checkInputFile(const fs::path& path, std::uintmax_t maxBytes) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (status.type() == fs::file_type::not_found) throw ProbeError(fmt::format("{}: no such file", path.string()));
    if (ec) throw ProbeError(fmt::format("{}: cannot read ({})", path.string(), ec.message()));
    if (status.type() != fs::file_type::regular)
        throw ProbeError(fmt::format("{}: is {}, not a regular file", path.string(), kindName(status.type())));
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec) throw ProbeError(fmt::format("{}: cannot read ({})", path.string(), ec.message()));
    if (size > maxBytes) throw ProbeError(fmt::format("{}: {} bytes, over the limit of {} bytes", path.string(), size, maxBytes));
    return size;
}

std::string readTextFile(const fs::path& path) {
    const std::uintmax_t size = checkInputFile(path, kMaxTextFileBytes);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ProbeError(fmt::format("{}: cannot open", path.string()));
    std::string text(static_cast<std::size_t>(size), '\0');
    in.read(text.data(), static_cast<std::streamsize>(size));
    // A file that shrank since it was measured; one that grew is read up to its measured size.
    text.resize(static_cast<std::size_t>(in.gcount()));
    return text;
}

} // namespace probe
