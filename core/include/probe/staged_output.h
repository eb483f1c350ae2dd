// Outputs that a run replaces whole or leaves as they were: folders (StagedOutput) and single files
// (StagedFile).
//
// Every file goes into a staging folder beside the output folder (".probefilter-<hash>-<pid>-<random>",
// so on the same file system, short whatever the output's name, and no other run's); commit() swaps
// the two folders in one renameat2(RENAME_EXCHANGE) (a plain rename when there is no output folder
// yet) and removes the old one. A run killed at any point leaves the previous output exactly as it
// was or the new one whole. A run holds an flock on its staging folder while it lives, so a killed
// run's folder is removed by the next run into the same folder, an interrupted one's at once
// (abandonAll(), from the command line's signal thread), and a failed run's on its way out with the
// parents it created.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace probe {

class StagedOutput {
public:
    // Checks, creating nothing, that `outDir` may be replaced, and throws ProbeError naming it
    // otherwise: it is not the root folder or a mount point, holds none of `inputs`, is a folder if it
    // exists, and is empty or probefilter's own (a report.json naming a command) unless `force`; its
    // nearest existing parent is a writable folder.
    StagedOutput(std::filesystem::path outDir, const std::vector<std::filesystem::path>& inputs, bool force);
    ~StagedOutput(); // removes the staging folder unless committed
    StagedOutput(const StagedOutput&) = delete;
    StagedOutput& operator=(const StagedOutput&) = delete;

    // Where to write a file that will appear as outDir/name (`name` may hold folders, e.g.
    // "sky/level_0.exr"). The first call creates the output's missing parents and the staging folder.
    std::filesystem::path file(const std::string& name);

    // Replaces the output folder with everything written (checking again that it may be replaced).
    void commit();

    const std::filesystem::path& outDir() const { return outDir_; }

    // Removes the staging folder of every StagedOutput and the staging file of every StagedFile not
    // yet committed; file(), path() and commit() fail afterwards. Safe to call from another thread; the
    // process is expected to end right after.
    static void abandonAll();

private:
    void checkReplaceable() const;
    void removeStaleStaging() const;
    void removeCreatedParents() const;

    std::filesystem::path outDir_;        // as given, for messages
    std::filesystem::path target_;        // absolute, symbolic links resolved
    std::filesystem::path staging_;       // empty until the first file()
    int stagingLock_ = -1;                // the staging folder, open and flocked
    std::filesystem::path createdParent_; // the outermost parent folder that file() created
    std::vector<std::filesystem::path> inputs_;
    bool force_ = false;
    bool committed_ = false;
};

// A single output file, written as ".NAME.XXXXXXXX.partial" beside it and renamed over it by commit():
// a run killed at any point leaves the previous file as it was (a killed run's staging file is removed
// by the next run's). The staging file is removed unless committed, when the StagedFile ends or at
// once on an interrupt (StagedOutput::abandonAll()).
class StagedFile {
public:
    // Checks, creating nothing, that `out` may be replaced, and throws ProbeError naming it otherwise:
    // its folder exists and is writable, and it is absent or a regular file (not a link).
    explicit StagedFile(std::filesystem::path out);
    ~StagedFile();
    StagedFile(const StagedFile&) = delete;
    StagedFile& operator=(const StagedFile&) = delete;

    // Where to write the file; the first call creates the staging file.
    std::filesystem::path path();
    // Moves the file written into place (checking again that it may be replaced).
    void commit();

private:
    friend class StagedOutput;
    void checkReplaceable() const;

    std::filesystem::path out_;     // absolute, the parents' links resolved
    std::filesystem::path shown_;   // as given, for messages
    std::filesystem::path staging_; // empty until the first path()
    int stagingLock_ = -1;          // the staging file, open and flocked
    bool committed_ = false;
};

} // namespace probe
