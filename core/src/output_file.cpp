#include "probe/output_file.h"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include "probe/error.h"

namespace probe {

int writeAll(int fd, std::string_view bytes) {
    for (std::size_t done = 0; done < bytes.size();) {
        const ssize_t written = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (written < 0 && errno == EINTR) continue;
        if (written <= 0) return written == 0 ? ENOSPC : errno;
        done += static_cast<std::size_t>(written);
    }
    return 0;
}

void writeFile(const std::filesystem::path& path, std::string_view bytes) {
    const auto fail = [&](int error) { return ProbeError(fmt::format("{}: cannot write ({})", path.string(), std::strerror(error))); };
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd < 0) throw fail(errno);
    if (const int error = writeAll(fd, bytes)) {
        ::close(fd);
        throw fail(error);
    }
    if (::close(fd) != 0) throw fail(errno);
}

} // namespace probe
