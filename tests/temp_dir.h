// A fresh folder per test, named by the process and the test, removed with the object.
#pragma once

#include <filesystem>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

namespace probetest {

struct TempDir {
    std::filesystem::path path;
    TempDir()
        : path(std::filesystem::temp_directory_path() /
               fmt::format("probe_test_{}_{}_{}", ::getpid(), ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name(),
                           ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~TempDir() { std::filesystem::remove_all(path); }
};

} // namespace probetest
