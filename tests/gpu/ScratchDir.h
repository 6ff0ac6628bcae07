// A scratch directory for test shaders, removed afterwards. The shader loader's root stays the
// real shaders/ directory: a stage given by absolute path still resolves `#include "lib/..."`
// and `#include "shared/..."` there.
#pragma once

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <unistd.h>

namespace testutil {

class ScratchDir {
public:
    ScratchDir() {
        static std::atomic<int> counter{0};
        mPath = std::filesystem::temp_directory_path() /
                ("penumbra-test-shaders-" + std::to_string(::getpid()) + "-" +
                 std::to_string(counter++));
        std::filesystem::create_directories(mPath);
    }
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(mPath, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;

    // Writes `text` to `name` in the directory; its absolute path.
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(mPath / name) << text;
        return (mPath / name).string();
    }

private:
    std::filesystem::path mPath;
};

} // namespace testutil
