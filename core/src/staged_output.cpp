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

#include "json_input.h"
#include "probe/error.h"
#include "probe/input_file.h"

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

// The output folder as a file system path: absolute, symbolic links resolved, no trailing "/".
fs::path resolve(const fs::path& path) {
    std::error_code ec;
    fs::path resolved = fs::weakly_canonical(fs::absolute(path), ec);
    if (ec) resolved = fs::absolute(path).lexically_normal();
    if (resolved.filename().empty() && resolved != resolved.root_path()) resolved = resolved.parent_path();
    return resolved;
}

bool contains(const fs::path& folder, const fs::path& path) {
    auto f = folder.begin(), p = path.begin();
    for (; f != folder.end(); ++f, ++p)
        if (p == path.end() || *f != *p) return false;
    return true;
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
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
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
    : outDir_(std::move(outDir)), target_(resolve(outDir_)), force_(force) {
    if (outDir_.empty()) throw ProbeError("the output folder is empty");
    for (const fs::path& input : inputs) {
        inputs_.push_back(fs::absolute(input).lexically_normal()); // a link inside the folder is its content too
        inputs_.push_back(resolve(input));
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
    std::error_code ec;
    const fs::file_status status = fs::status(target_, ec);
    if (!fs::exists(status)) return;
    if (!fs::is_directory(status)) fail(outDir_, "exists and is not a folder");
    struct stat folder = {}, parent = {};
    if (::stat(target_.c_str(), &folder) == 0 && ::stat(target_.parent_path().c_str(), &parent) == 0 && folder.st_dev != parent.st_dev)
        fail(outDir_, "is a mount point, which cannot be replaced whole; name a folder inside it");
    if (!force_ && !fs::is_empty(target_, ec) && !writtenByProbefilter(target_))
        fail(outDir_,
             "is not empty and holds no report.json of probefilter's; remove it, name another folder or pass --force to replace it");
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
    std::error_code ec;
    fs::remove_all(staging_, ec);
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
    for (const StagedFile* file : fileRegistry) {
        std::error_code ec;
        if (!file->committed_) fs::remove(file->staging_, ec);
    }
}

StagedFile::StagedFile(fs::path out) : out_(std::move(out)) {
    staging_ = out_.parent_path() / fmt::format(".{}.partial", out_.filename().string());
    const std::lock_guard lock(registryMutex);
    fileRegistry.push_back(this);
}

StagedFile::~StagedFile() {
    const std::lock_guard lock(registryMutex);
    fileRegistry.erase(std::find(fileRegistry.begin(), fileRegistry.end(), this));
    std::error_code ec;
    if (!committed_) fs::remove(staging_, ec);
}

fs::path StagedFile::path() const {
    const std::lock_guard lock(registryMutex);
    if (abandoned) fail(out_, "interrupted");
    return staging_;
}

void StagedFile::commit() {
    const std::lock_guard lock(registryMutex);
    if (abandoned) fail(out_, "interrupted");
    std::error_code ec;
    fs::rename(staging_, out_, ec);
    if (ec) fail(out_, fmt::format("cannot move the output into place ({})", ec.message()));
    committed_ = true;
}

} // namespace probe
