// Shared by the fuzz targets: the input size bound, and a per-process temporary folder for the
// readers that take a path.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace probe_fuzz {

// Inputs above this are skipped: every reader refuses or reads them in time linear in the size,
// so larger inputs find nothing new and only slow the run down.
inline constexpr std::size_t kMaxInputBytes = 256 * 1024;

// A folder of its own per process (libFuzzer may run several jobs side by side), removed at exit.
class TempFolder {
public:
    TempFolder() : path_(std::filesystem::temp_directory_path() / ("probefilter-fuzz-" + std::to_string(getpid()))) {
        std::filesystem::create_directories(path_);
    }
    ~TempFolder() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempFolder(const TempFolder&) = delete;
    TempFolder& operator=(const TempFolder&) = delete;

    const std::filesystem::path& path() const { return path_; }

    // Writes the input to `name` in the folder and returns its path.
    std::filesystem::path write(const std::string& name, const std::uint8_t* data, std::size_t size) const {
        const std::filesystem::path file = path_ / name;
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
        return file;
    }

private:
    std::filesystem::path path_;
};

inline const TempFolder& tempFolder() {
    static const TempFolder folder;
    return folder;
}

} // namespace probe_fuzz
