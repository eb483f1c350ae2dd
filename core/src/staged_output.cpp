#include "probe/staged_output.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <random>
#include <thread>

#include <fcntl.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "probe/error.h"
#include "probe/input_file.h"
#include "probe/json_input.h"

namespace probe {

namespace fs = std::filesystem;

namespace {

// Every StagedOutput and StagedFile alive, for abandonAll(); the mutex also keeps abandonAll() from
// removing a staging folder or file while file(), path() or commit() works on it.
std::mutex registryMutex;
std::vector<StagedOutput*> registry;
std::vector<StagedFile*> fileRegistry;
bool abandoned = false;

[[noreturn]] void fail(const fs::path& path, const std::string& problem) {
    throw ProbeError(fmt::format("{}: {}", path.string(), problem));
}

// An output as a file system path: absolute, no trailing "/", the links of its parents resolved but
// not its own name's (an output is replaced, never reached through a link).
fs::path outputPath(const fs::path& path) {
    fs::path absolute = fs::absolute(path).lexically_normal();
    if (absolute.filename().empty() && absolute != absolute.root_path()) absolute = absolute.parent_path();
    if (absolute == absolute.root_path()) return absolute;
    std::error_code ec;
    const fs::path parent = fs::weakly_canonical(absolute.parent_path(), ec);
    return (ec ? absolute.parent_path() : parent) / absolute.filename();
}

// An input as a file system path, every link resolved.
fs::path inputPath(const fs::path& path) {
    std::error_code ec;
    const fs::path resolved = fs::weakly_canonical(fs::absolute(path), ec);
    return ec ? fs::absolute(path).lexically_normal() : resolved;
}

bool contains(const fs::path& folder, const fs::path& path) {
    auto f = folder.begin(), p = path.begin();
    for (; f != folder.end(); ++f, ++p)
        if (p == path.end() || *f != *p) return false;
    return true;
}

// The mount points of this process's namespace (/proc/self/mountinfo's fifth field, octal escapes
// decoded); empty where it cannot be read.
std::vector<fs::path> mountPoints() {
    std::vector<fs::path> points;
    std::FILE* file = std::fopen("/proc/self/mountinfo", "re");
    if (!file) return points;
    char* line = nullptr;
    std::size_t capacity = 0;
    while (::getline(&line, &capacity, file) > 0) {
        std::string field;
        const char* c = line;
        for (int skip = 0; skip < 4 && *c; ++c)
            if (*c == ' ') ++skip;
        for (; *c && *c != ' ' && *c != '\n'; ++c) {
            if (c[0] == '\\' && c[1] && c[2] && c[3]) {
                field += static_cast<char>(std::strtol(std::string(c + 1, 3).c_str(), nullptr, 8));
                c += 3;
            } else field += *c;
        }
        points.emplace_back(field);
    }
    std::free(line);
    std::fclose(file);
    return points;
}

// Throws unless the existing output folder `folder` can be removed whole without leaving it: nothing
// inside is another file system (its files are not the output's), and every folder inside can be
// listed and emptied. Links inside are removed, never followed.
void checkRemovable(const fs::path& shown, const fs::path& folder, dev_t device) {
    for (const fs::path& point : mountPoints())
        if (point != folder && contains(folder, point))
            fail(shown, fmt::format("holds the mount point {}, whose files are not the output's; unmount it or name another folder",
                                    point.string()));
    const auto checkFolder = [&](const fs::path& path) {
        if (::access(path.c_str(), R_OK | W_OK | X_OK) != 0)
            fail(shown, fmt::format("cannot replace it: {} inside it cannot be emptied ({})", path.string(), std::strerror(errno)));
    };
    checkFolder(folder);
    std::error_code ec;
    for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        struct stat entry = {};
        if (::lstat(it->path().c_str(), &entry) != 0) continue; // gone meanwhile
        if (entry.st_dev != device)
            fail(shown, fmt::format("holds {}, on another file system; unmount it or name another folder", it->path().string()));
        if (S_ISDIR(entry.st_mode)) checkFolder(it->path());
    }
    if (ec) fail(shown, fmt::format("cannot replace it: cannot list what it holds ({})", ec.message()));
}

// Removes `path` and everything in it, never following a link nor entering another file system
// (a mount made after checkRemovable). Returns the first entry that stays, empty if none.
fs::path removeTree(const fs::path& path, dev_t device) {
    struct stat entry = {};
    if (::lstat(path.c_str(), &entry) != 0) return errno == ENOENT ? fs::path() : path;
    if (entry.st_dev != device) return path;
    fs::path stays;
    if (S_ISDIR(entry.st_mode)) {
        std::error_code ec;
        std::vector<fs::path> children;
        for (const fs::directory_entry& child : fs::directory_iterator(path, ec)) children.push_back(child.path());
        if (ec) return path;
        for (const fs::path& child : children)
            if (fs::path left = removeTree(child, device); stays.empty()) stays = left;
    }
    if (::remove(path.c_str()) != 0 && stays.empty()) stays = path;
    return stays;
}

// Short and fixed for a folder name: FNV-1a of it.
std::string nameHash(const std::string& name) {
    std::uint32_t h = 2166136261u;
    for (unsigned char c : name) h = (h ^ c) * 16777619u;
    return fmt::format("{:08x}", h);
}

// Whether the folder holds a report.json naming a command: read as an input file (a regular file,
// bounded in size, nesting and duplicate keys), so that a FIFO or a huge file there is not ours.
bool writtenByProbefilter(const fs::path& folder) {
    try {
        const fs::path path = folder / "report.json";
        const nlohmann::json report = parseJsonFile(readTextFile(path), path, "report");
        return report.is_object() && report.contains("command") && report["command"].is_string();
    } catch (const ProbeError&) {
        return false;
    }
}

// A staging folder is live while its run holds an flock on it: the lock goes with the process,
// whatever PID namespace it ran in, where its PID alone could name another process. A dead run's
// folder is removed under the lock, so that a run that has just made a folder and not yet locked it
// finds it taken or gone (lockNewStaging), never removed from under it later.
void removeIfStale(const fs::path& folder) {
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) return;
    std::error_code ec;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) fs::remove_all(folder, ec);
    ::close(fd);
}

// The staging folder just made at `folder`, open and locked; -1 if another run took it for a dead
// run's in the instant between (it holds the lock, or has removed the folder).
int lockNewStaging(const fs::path& folder) {
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return -1;
    struct stat opened = {}, named = {};
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0 || ::fstat(fd, &opened) != 0 || opened.st_nlink == 0 || ::stat(folder.c_str(), &named) != 0 ||
        named.st_dev != opened.st_dev || named.st_ino != opened.st_ino) {
        ::close(fd);
        return -1;
    }
    return fd;
}

} // namespace

StagedOutput::StagedOutput(fs::path outDir, const std::vector<fs::path>& inputs, bool force)
    : outDir_(std::move(outDir)), target_(outputPath(outDir_)), force_(force) {
    if (outDir_.empty()) throw ProbeError("the output folder is empty");
    for (const fs::path& input : inputs) {
        inputs_.push_back(fs::absolute(input).lexically_normal()); // a link inside the folder is its content too
        inputs_.push_back(inputPath(input));
    }
    checkReplaceable();
    fs::path parent = target_.parent_path();
    std::error_code ec;
    while (!fs::exists(parent, ec) && parent != parent.root_path()) parent = parent.parent_path();
    if (!fs::is_directory(parent, ec)) fail(outDir_, fmt::format("cannot create it: {} is not a folder", parent.string()));
    if (::access(parent.c_str(), W_OK | X_OK) != 0)
        fail(outDir_,
             fmt::format("cannot create it: {} is not writable (the output folder is replaced whole, from beside it)", parent.string()));
    const std::lock_guard lock(registryMutex);
    registry.push_back(this);
}

StagedOutput::~StagedOutput() {
    const std::lock_guard lock(registryMutex);
    registry.erase(std::find(registry.begin(), registry.end(), this));
    if (stagingLock_ >= 0) ::close(stagingLock_);
    if (committed_) return;
    std::error_code ec;
    if (!staging_.empty()) fs::remove_all(staging_, ec);
    removeCreatedParents();
}

// The parents of the output folder that file() created, innermost first, as long as they are empty.
void StagedOutput::removeCreatedParents() const {
    std::error_code ec;
    if (!createdParent_.empty())
        for (fs::path p = target_.parent_path(); fs::remove(p, ec) && p != createdParent_;) p = p.parent_path();
}

void StagedOutput::checkReplaceable() const {
    if (target_ == target_.root_path()) fail(outDir_, "refusing to replace the root folder");
    for (const fs::path& input : inputs_)
        if (contains(target_, input)) fail(outDir_, fmt::format("holds the input {}; name another output folder", input.string()));
    struct stat folder = {}, parent = {};
    if (::lstat(target_.c_str(), &folder) != 0) {
        if (errno == ENOENT) return;
        fail(outDir_, fmt::format("cannot replace it ({})", std::strerror(errno)));
    }
    if (S_ISLNK(folder.st_mode)) fail(outDir_, "is a symbolic link; name the folder itself (an output is replaced, never followed)");
    if (!S_ISDIR(folder.st_mode)) fail(outDir_, "exists and is not a folder");
    if (::stat(target_.parent_path().c_str(), &parent) == 0 && folder.st_dev != parent.st_dev)
        fail(outDir_, "is a mount point, which cannot be replaced whole; name a folder inside it");
    std::error_code ec;
    if (!force_ && !fs::is_empty(target_, ec) && !writtenByProbefilter(target_))
        fail(outDir_,
             "is not empty and holds no report.json of probefilter's; remove it, name another folder or pass --force to replace it");
    checkRemovable(outDir_, target_, folder.st_dev);
}

// The staging folders of earlier runs into the same folder that were killed (none holds its lock).
void StagedOutput::removeStaleStaging() const {
    const std::string prefix = fmt::format(".probefilter-{}-", nameHash(target_.filename().string()));
    std::error_code ec;
    for (const fs::directory_entry& entry : fs::directory_iterator(target_.parent_path(), ec)) {
        const std::string name = entry.path().filename().string();
        // Not a ".old" folder (commit() without RENAME_EXCHANGE), which holds a previous output.
        if (name.rfind(prefix, 0) != 0 || name.find('.', 1) != std::string::npos) continue;
        removeIfStale(entry.path());
    }
}

fs::path StagedOutput::file(const std::string& name) {
    const std::lock_guard lock(registryMutex);
    if (abandoned) fail(outDir_, "interrupted");
    std::error_code ec;
    if (staging_.empty()) {
        for (fs::path p = target_.parent_path(); !fs::exists(p, ec) && p != p.root_path(); p = p.parent_path()) createdParent_ = p;
        fs::create_directories(target_.parent_path(), ec);
        if (ec) fail(outDir_, fmt::format("cannot create its parent folder ({})", ec.message()));
        removeStaleStaging();
        // A name no other run has (the PID and a random suffix, created exclusively), locked while
        // this run lives.
        std::random_device random;
        for (int attempt = 0; staging_.empty(); ++attempt) {
            if (attempt == 16) fail(outDir_, "cannot create its staging folder (16 names taken)");
            const fs::path candidate = target_.parent_path() / fmt::format(".probefilter-{}-{}-{:08x}",
                                                                           nameHash(target_.filename().string()), ::getpid(), random());
            if (::mkdir(candidate.c_str(), 0777) != 0) {
                if (errno == EEXIST) continue;
                fail(outDir_, fmt::format("cannot create its staging folder ({})", std::strerror(errno)));
            }
            stagingLock_ = lockNewStaging(candidate);
            if (stagingLock_ >= 0) staging_ = candidate;
        }
    }
    const fs::path path = staging_ / name;
    fs::create_directories(path.parent_path(), ec);
    if (ec) fail(outDir_ / name, fmt::format("cannot create its folder ({})", ec.message()));
    return path;
}

void StagedOutput::commit() {
    if (staging_.empty()) file("."); // nothing written: an empty output folder
    // For tests/cli_output_folder.sh, which kills runs at random points: a pause with the new output
    // staged whole, just before the swap.
    if (const char* pause = std::getenv("PROBEFILTER_TEST_PAUSE_BEFORE_SWAP_MS"))
        std::this_thread::sleep_for(std::chrono::milliseconds(std::atoi(pause)));
    const std::lock_guard lock(registryMutex);
    if (abandoned) fail(outDir_, "interrupted");
    checkReplaceable();
    // Swap the folders; the staging name then holds the previous output, which is removed.
    int result = ::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE);
    if (result != 0 && errno == ENOENT) result = ::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_NOREPLACE);
    if (result != 0 && (errno == EINVAL || errno == ENOSYS)) {
        // A file system without RENAME_EXCHANGE: the output folder is briefly absent, never mixed.
        const fs::path old = staging_.string() + ".old";
        result = std::rename(target_.c_str(), old.c_str());
        const bool moved = result == 0;
        if (moved || errno == ENOENT) result = std::rename(staging_.c_str(), target_.c_str());
        if (result == 0) staging_ = old;
        else if (moved) std::rename(old.c_str(), target_.c_str());
    }
    if (result != 0) fail(outDir_, fmt::format("cannot move the output into place ({})", std::strerror(errno)));
    committed_ = true;
    struct stat previous = {};
    if (::lstat(staging_.c_str(), &previous) != 0) return;
    if (const fs::path stays = removeTree(staging_, previous.st_dev); !stays.empty())
        fail(outDir_, fmt::format("is written, but the previous output's {} cannot be removed; what is left of it is in {}", stays.string(),
                                  staging_.string()));
}

void StagedOutput::abandonAll() {
    const std::lock_guard lock(registryMutex);
    abandoned = true;
    for (const StagedOutput* output : registry) {
        if (output->committed_ || output->staging_.empty()) continue;
        // A file the run is writing at the same moment may appear during the removal: try again.
        std::error_code ec;
        for (int attempt = 0; attempt < 5 && fs::exists(output->staging_, ec); ++attempt) fs::remove_all(output->staging_, ec);
        output->removeCreatedParents();
    }
    for (const StagedFile* file : fileRegistry)
        if (!file->committed_ && !file->staging_.empty()) ::unlink(file->staging_.c_str());
}

StagedFile::StagedFile(fs::path out) : out_(outputPath(out)), shown_(std::move(out)) {
    const fs::path parent = out_.parent_path();
    struct stat folder = {};
    if (::stat(parent.c_str(), &folder) != 0 || !S_ISDIR(folder.st_mode))
        fail(shown_, fmt::format("cannot write it: {} is not a folder", parent.string()));
    if (::access(parent.c_str(), W_OK | X_OK) != 0)
        fail(shown_, fmt::format("cannot write it: {} is not writable (the file is replaced whole, from beside it)", parent.string()));
    checkReplaceable();
    const std::lock_guard lock(registryMutex);
    fileRegistry.push_back(this);
}

StagedFile::~StagedFile() {
    const std::lock_guard lock(registryMutex);
    fileRegistry.erase(std::find(fileRegistry.begin(), fileRegistry.end(), this));
    if (!committed_ && !staging_.empty()) ::unlink(staging_.c_str());
    if (stagingLock_ >= 0) ::close(stagingLock_);
}

// Nothing but a regular file is replaced: not a folder, a device, a FIFO or a socket, and not a
// symbolic link, which would be replaced by a file rather than followed.
void StagedFile::checkReplaceable() const {
    struct stat entry = {};
    if (::lstat(out_.c_str(), &entry) != 0) return;
    if (S_ISLNK(entry.st_mode)) fail(shown_, "is a symbolic link; name the file itself (an output is replaced, never followed)");
    if (!S_ISREG(entry.st_mode)) fail(shown_, "exists and is not a regular file");
}

fs::path StagedFile::path() {
    const std::lock_guard lock(registryMutex);
    if (abandoned) fail(shown_, "interrupted");
    if (!staging_.empty()) return staging_;
    // The staging files of killed runs (none holds its lock), then a name no other run has, created
    // exclusively (nothing planted there is followed) and locked while this run lives.
    const std::string prefix = fmt::format(".{}.", out_.filename().string());
    std::error_code ec;
    for (const fs::directory_entry& entry : fs::directory_iterator(out_.parent_path(), ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() == prefix.size() + 16 && name.starts_with(prefix) && name.ends_with(".partial")) {
            const int fd = ::open(entry.path().c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
            struct stat opened = {};
            if (fd >= 0 && ::fstat(fd, &opened) == 0 && S_ISREG(opened.st_mode) && ::flock(fd, LOCK_EX | LOCK_NB) == 0)
                ::unlink(entry.path().c_str());
            if (fd >= 0) ::close(fd);
        }
    }
    std::random_device random;
    for (int attempt = 0; staging_.empty(); ++attempt) {
        if (attempt == 16) fail(shown_, "cannot create its staging file (16 names taken)");
        const fs::path candidate = out_.parent_path() / fmt::format("{}{:08x}.partial", prefix, random());
        const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
        if (fd < 0) {
            if (errno == EEXIST) continue;
            fail(shown_, fmt::format("cannot create its staging file ({})", std::strerror(errno)));
        }
        // Locked, and still there: another run's cleanup may have taken it in the instant between.
        struct stat opened = {};
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0 || ::fstat(fd, &opened) != 0 || opened.st_nlink == 0) {
            ::close(fd);
            continue;
        }
        stagingLock_ = fd;
        staging_ = candidate;
    }
    return staging_;
}

void StagedFile::commit() {
    const std::lock_guard lock(registryMutex);
    if (abandoned) fail(shown_, "interrupted");
    checkReplaceable();
    if (::rename(staging_.c_str(), out_.c_str()) != 0)
        fail(shown_, fmt::format("cannot move the output into place ({})", std::strerror(errno)));
    committed_ = true;
}

} // namespace probe
