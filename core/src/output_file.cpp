#include "probe/output_file.h"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include "probe/error.h"

namespace probe {

void writeFile(const std::filesystem::path& path, std::string_view bytes) {
    const auto fail = [&] { return ProbeError(fmt::format("{}: cannot write ({})", path.string(), std::strerror(errno))); };
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) throw fail();
    for (std::size_t done = 0; done < bytes.size();) {
        const ssize_t written = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (written < 0 && errno == EINTR) continue;
        if (written <= 0) {
            if (written == 0) errno = ENOSPC;
            const ProbeError error = fail();
            ::close(fd);
            throw error;
        }
        done += static_cast<std::size_t>(written);
    }
    if (::close(fd) != 0) throw fail();
}

} // namespace probe
