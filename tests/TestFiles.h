// A fresh temporary directory per test, removed afterwards: nothing a test writes lands in the
// source tree, and tests running at the same time (ctest -j) never share a directory.
#pragma once

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <random>
#include <string>
#include <system_error>
#include <unistd.h>

namespace testutil {

// mDir is <temp>/penumbra-<prefix>-<pid>-<counter>-<random>, created in SetUp and removed with
// everything in it in TearDown.
class TempDirTest : public ::testing::Test {
protected:
    explicit TempDirTest(std::string prefix) : mPrefix(std::move(prefix)) {}

    void SetUp() override {
        static std::atomic<int> counter{0};
        mDir = std::filesystem::temp_directory_path() /
               ("penumbra-" + mPrefix + "-" + std::to_string(::getpid()) + "-" +
                std::to_string(counter++) + "-" + std::to_string(std::random_device{}()));
        std::filesystem::create_directories(mDir);
    }
    void TearDown() override {
        std::error_code ec;
        std::filesystem::remove_all(mDir, ec);
    }

    std::filesystem::path mDir;

private:
    std::string mPrefix;
};

} // namespace testutil
