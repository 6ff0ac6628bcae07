// penumbra-soak's command line: bad input exits 2 with the flag named, before any scene is loaded
// or GL is set up; --size and --samples have the limits every app shares (apps/Flags.h).
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

const std::string kSoak = std::string(PENUMBRA_BIN_DIR) + "/penumbra-soak";
const std::string kLevel = std::string(PENUMBRA_SHARED_DIR) + "/levels/oa_dm4.glb";

struct RunResult {
    int exitCode = -1;
    std::string output;
};

RunResult soak(const std::string& args) {
    std::random_device rd;
    const fs::path log = fs::temp_directory_path() / ("penumbra-soak-" + std::to_string(rd()));
    const std::string cmd =
        kSoak + " --scene '" + kLevel + "' " + args + " > '" + log.string() + "' 2>&1";
    const int status = std::system(cmd.c_str());
    RunResult r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::stringstream ss;
    ss << std::ifstream(log).rdbuf();
    r.output = ss.str();
    fs::remove(log);
    return r;
}

TEST(SoakCli, OutOfRangeFlagsAreBadInput) {
    const std::pair<std::string, std::string> cases[] = {
        {"--size 0x64", "penumbra-soak: error: --size: each side must be between 1 and 16384, "
                        "got '0x64'"},
        {"--size 16385x64", "--size: each side must be between 1 and 16384, got '16385x64'"},
        {"--size big", "--size: expected WIDTHxHEIGHT (e.g. 128x128), got 'big'"},
        {"--samples 0", "penumbra-soak: error: --samples must be between 1 and 65536"},
        {"--samples 65537", "--samples must be between 1 and 65536"},
        {"--frames 0", "--frames must be between 1 and 10000000"},
        {"--method nope", "nope"},
    };
    for (const auto& [args, needle] : cases) {
        const RunResult r = soak(args);
        EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.output;
        EXPECT_NE(r.output.find(needle), std::string::npos) << args << "\n" << r.output;
        EXPECT_EQ(r.output.find("renderer:"), std::string::npos) << "GL set up first: " << r.output;
    }
}

TEST(SoakCli, ParseErrorsExitTwo) {
    const RunResult r = soak("--bogus");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--bogus"), std::string::npos) << r.output;
    EXPECT_EQ(soak("--help").exitCode, 0);
}

} // namespace
