// Output folders: replaced whole or left as they were; refused, with nothing created, where a
// replacement would destroy what probefilter did not write. Single output files: replaced whole on
// commit, or left as they were with no staging file.
#include <fstream>
#include <iterator>
#include <set>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "probe/error.h"
#include "probe/staged_output.h"
#include "temp_dir.h"

using namespace probe;
using probetest::TempDir;
namespace fs = std::filesystem;

namespace {

void writeText(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string readText(const fs::path& path) {
    std::ifstream in(path);
    return {std::istreambuf_iterator<char>(in), {}};
}

// Whether `use` throws ProbeError.
template <class Use>
bool refused(Use use) {
    try {
        use();
    } catch (const ProbeError&) {
        return true;
    }
    return false;
}

// A run's output: the files, and a report.json that marks the folder as probefilter's.
void writeRun(StagedOutput& output, const std::vector<std::string>& names) {
    for (const std::string& name : names) writeText(output.file(name), name);
    writeText(output.file("report.json"), R"({"command": "filter"})");
}

std::set<std::string> entries(const fs::path& folder) {
    std::set<std::string> names;
    for (const fs::directory_entry& e : fs::directory_iterator(folder)) names.insert(e.path().filename().string());
    return names;
}

} // namespace

TEST(StagedOutput, AppearsOnlyOnCommit) {
    TempDir dir;
    const fs::path out = dir.path / "result";
    {
        StagedOutput staged(out, {}, false);
        writeRun(staged, {"level_0.exr"});
        EXPECT_FALSE(fs::exists(out));
    }
    EXPECT_TRUE(entries(dir.path).empty());
    {
        StagedOutput staged(out, {}, false);
        writeRun(staged, {"level_0.exr"});
        staged.commit();
    }
    EXPECT_EQ(entries(out), (std::set<std::string>{"level_0.exr", "report.json"}));
    EXPECT_EQ(entries(dir.path), std::set<std::string>{"result"});
}

TEST(StagedOutput, ReplacesTheFolderWhole) {
    TempDir dir;
    const fs::path out = dir.path / "result";
    StagedOutput first(out, {}, false);
    writeRun(first, {"level_0.exr", "level_1.exr", "level_2.exr", "sky/probe.ktx2"});
    first.commit();
    StagedOutput second(out, {}, false);
    writeRun(second, {"level_0.exr"});
    second.commit();
    EXPECT_EQ(entries(out), (std::set<std::string>{"level_0.exr", "report.json"}));
    EXPECT_EQ(entries(dir.path), std::set<std::string>{"result"});
}

TEST(StagedOutput, RefusesWhatItMustNotReplaceAndCreatesNothing) {
    TempDir dir;
    fs::create_directories(dir.path / "inputs");
    writeText(dir.path / "inputs/probe.exr", "x");
    fs::create_directories(dir.path / "notes");
    writeText(dir.path / "notes/todo.txt", "keep");
    writeText(dir.path / "a-file", "x");
    EXPECT_THROW(StagedOutput("/", {}, true), ProbeError);
    EXPECT_THROW(StagedOutput(dir.path / "inputs", {dir.path / "inputs/probe.exr"}, true), ProbeError);
    EXPECT_THROW(StagedOutput(dir.path, {dir.path / "inputs/probe.exr"}, true), ProbeError);
    EXPECT_THROW(StagedOutput(dir.path / "notes", {}, false), ProbeError);
    EXPECT_THROW(StagedOutput(dir.path / "a-file", {}, true), ProbeError);
    EXPECT_THROW(StagedOutput(dir.path / "a-file/deeper/out", {}, true), ProbeError);
    EXPECT_EQ(entries(dir.path), (std::set<std::string>{"a-file", "inputs", "notes"}));
    EXPECT_EQ(entries(dir.path / "notes"), std::set<std::string>{"todo.txt"});

    // Refused after the checks (bad input found later): the missing parents are not created either.
    { StagedOutput unused(dir.path / "new/parents/out", {}, false); }
    EXPECT_FALSE(fs::exists(dir.path / "new"));

    // --force replaces a folder that probefilter did not write.
    StagedOutput forced(dir.path / "notes", {}, true);
    writeRun(forced, {"level_0.exr"});
    forced.commit();
    EXPECT_EQ(entries(dir.path / "notes"), (std::set<std::string>{"level_0.exr", "report.json"}));
}

TEST(StagedOutput, LongNamesAndEmptyFolders) {
    TempDir dir;
    const fs::path out = dir.path / std::string(250, 'n');
    StagedOutput staged(out, {}, false);
    writeRun(staged, {"level_0.exr"});
    staged.commit();
    EXPECT_TRUE(fs::exists(out / "level_0.exr"));

    fs::create_directories(dir.path / "empty");
    StagedOutput intoEmpty(dir.path / "empty", {}, false);
    writeRun(intoEmpty, {"level_0.exr"});
    intoEmpty.commit();
    EXPECT_EQ(entries(dir.path / "empty"), (std::set<std::string>{"level_0.exr", "report.json"}));
}

TEST(StagedOutput, AKilledRunsStagingIsRemovedByTheNextRun) {
    TempDir dir;
    const fs::path out = dir.path / "result";
    const pid_t child = ::fork();
    if (child == 0) {
        StagedOutput staged(out, {}, false);
        writeRun(staged, {"level_0.exr"});
        ::raise(SIGKILL);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status));
    EXPECT_EQ(entries(dir.path).size(), 1u); // the killed run's staging folder
    StagedOutput next(out, {}, false);
    writeRun(next, {"level_1.exr"});
    next.commit();
    EXPECT_EQ(entries(dir.path), std::set<std::string>{"result"});
    EXPECT_EQ(entries(out), (std::set<std::string>{"level_1.exr", "report.json"}));
}

TEST(StagedOutput, AbandonAllRemovesStaging) {
    TempDir dir;
    const pid_t child = ::fork();
    if (child == 0) {
        StagedOutput staged(dir.path / "result", {}, false);
        writeRun(staged, {"level_0.exr"});
        StagedFile file(dir.path / "probe.exr");
        writeText(file.path(), "new");
        StagedOutput::abandonAll();
        const bool allRefused =
            refused([&] { staged.file("level_1.exr"); }) && refused([&] { file.path(); }) && refused([&] { file.commit(); });
        ::_exit(allRefused ? 0 : 1); // no destructors: only abandonAll() may have cleaned up
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0);
    EXPECT_TRUE(entries(dir.path).empty());
}

TEST(StagedFile, ReplacesTheFileOnlyOnCommit) {
    TempDir dir;
    const fs::path out = dir.path / "probe.exr";
    writeText(out, "old");
    {
        StagedFile staged(out);
        writeText(staged.path(), "new");
        EXPECT_EQ(entries(dir.path), (std::set<std::string>{staged.path().filename().string(), "probe.exr"}));
    }
    EXPECT_EQ(entries(dir.path), std::set<std::string>{"probe.exr"});
    EXPECT_EQ(readText(out), "old");
    {
        StagedFile staged(out);
        writeText(staged.path(), "new");
        staged.commit();
    }
    EXPECT_EQ(entries(dir.path), std::set<std::string>{"probe.exr"});
    EXPECT_EQ(readText(out), "new");
}

TEST(StagedFile, RefusesWhatIsNotARegularFileAndFollowsNoLink) {
    TempDir dir;
    writeText(dir.path / "precious", "precious");
    fs::create_symlink("precious", dir.path / "link");
    fs::create_symlink("nowhere", dir.path / "dangling");
    fs::create_directories(dir.path / "folder");
    ASSERT_EQ(::mkfifo((dir.path / "fifo").c_str(), 0600), 0);
    for (const char* name : {"link", "dangling", "folder", "fifo", "missing/probe.exr"})
        EXPECT_THROW(StagedFile(dir.path / name), ProbeError) << name;

    // A link planted at the name a killed run's staging file has is neither followed nor removed.
    const fs::path planted = dir.path / ".probe.exr.0badf00d.partial";
    fs::create_symlink("precious", planted);
    {
        StagedFile staged(dir.path / "probe.exr");
        writeText(staged.path(), "new");
        staged.commit();
    }
    EXPECT_EQ(readText(dir.path / "probe.exr"), "new");
    EXPECT_TRUE(fs::is_symlink(planted));
    EXPECT_EQ(readText(dir.path / "precious"), "precious");
}

TEST(StagedFile, AKilledRunsStagingFileIsRemovedByTheNextRun) {
    TempDir dir;
    const fs::path out = dir.path / "probe.exr";
    const pid_t child = ::fork();
    if (child == 0) {
        StagedFile staged(out);
        writeText(staged.path(), "killed");
        ::raise(SIGKILL);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status));
    EXPECT_EQ(entries(dir.path).size(), 1u); // the killed run's staging file
    StagedFile live(out);
    writeText(live.path(), "live");
    {
        StagedFile other(out); // a second run beside a live one leaves the live one's file
        writeText(other.path(), "other");
        EXPECT_EQ(entries(dir.path).size(), 2u);
    }
    live.commit();
    EXPECT_EQ(entries(dir.path), std::set<std::string>{"probe.exr"});
    EXPECT_EQ(readText(out), "live");
}

TEST(StagedOutput, RefusesASymbolicLinkWhereverItPoints) {
    TempDir dir;
    fs::create_directories(dir.path / "folder");
    writeText(dir.path / "folder/report.json", R"({"command": "filter"})");
    fs::create_symlink("folder", dir.path / "to-folder");
    fs::create_symlink("nowhere", dir.path / "dangling");
    fs::create_symlink("loop", dir.path / "loop");
    for (const char* name : {"to-folder", "to-folder/", "dangling", "loop"})
        EXPECT_THROW(StagedOutput(dir.path / name, {}, true), ProbeError) << name;
    EXPECT_EQ(entries(dir.path), (std::set<std::string>{"dangling", "folder", "loop", "to-folder"}));
    EXPECT_EQ(entries(dir.path / "folder"), std::set<std::string>{"report.json"});
}
