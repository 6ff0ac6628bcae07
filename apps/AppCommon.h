// What the apps share: flag checks (--size, --seed, output folders), command-line error
// messages, and the CPU's name for their reports.
#pragma once

#include <geometry/core/Error.h>

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <utility>

namespace apps {

// --size WIDTHxHEIGHT: the format, then each side in [minSide, maxSide]; a geometry::InputError
// naming the flag otherwise (bad input: exit 2).
inline std::pair<int, int> parseSize(const std::string& s, int minSide, int maxSide,
                                     const char* example) {
    static const std::regex re(R"((\d+)x(\d+))");
    std::smatch m;
    if (!std::regex_match(s, m, re))
        throw geometry::InputError(std::string("--size: expected WIDTHxHEIGHT (e.g. ") + example +
                                   "), got '" + s + "'");
    // Any number of digits is the right format; more than 9 is only out of range.
    auto side = [](const std::string& digits) {
        return digits.size() > 9 ? 1'000'000'000 : std::stoi(digits);
    };
    const int w = side(m[1]), h = side(m[2]);
    if (w < minSide || h < minSide || w > maxSide || h > maxSide)
        throw geometry::InputError("--size: each side must be between " + std::to_string(minSide) +
                                   " and " + std::to_string(maxSide) + ", got '" + s + "'");
    return {w, h};
}

// --seed: parsed wider than the seed so that a negative or too large value gets this message,
// not a bare conversion error.
inline std::uint32_t checkSeed(std::int64_t seed) {
    if (seed < 0 || seed > std::int64_t(UINT32_MAX))
        throw geometry::InputError("--seed must be between 0 and 4294967295, got " +
                                   std::to_string(seed));
    return std::uint32_t(seed);
}

// An output folder named by `flag` (e.g. "--out") can be created or written: it is a folder, or
// its nearest existing ancestor is a writable folder. Checked before any work, so that a mistake
// is bad input found at once, not an error after the rendering.
inline void checkOutputFolder(const char* flag, const std::filesystem::path& folder) {
    namespace fs = std::filesystem;
    const std::string name = std::string(flag) + ": '" + folder.string() + "'";
    if (folder.empty()) throw geometry::InputError(std::string(flag) + ": empty folder name");
    std::error_code ec;
    if (fs::exists(folder, ec) && !fs::is_directory(folder, ec))
        throw geometry::InputError(name + " exists and is not a folder");
    fs::path existing = fs::absolute(folder, ec);
    while (!existing.empty() && !fs::exists(existing, ec) && existing.has_relative_path())
        existing = existing.parent_path();
    if (!fs::is_directory(existing, ec))
        throw geometry::InputError(name + " cannot be created: '" + existing.string() +
                                   "' is not a folder");
    if (access(existing.c_str(), W_OK | X_OK) != 0)
        throw geometry::InputError(name + " cannot be written: no write permission in '" +
                                   existing.string() + "'");
}

// A command-line parse error (the CLI11 exception's message) in the form of every other error:
// "PROGRAM: error: MESSAGE" and a hint; returns the bad-input exit code 2.
inline int reportParseError(const char* program, const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\nRun with --help for more information.\n", program,
                 e.what());
    return 2;
}

// The CPU model from /proc/cpuinfo ("unknown" when it cannot be read), stated beside timings.
inline std::string cpuModel() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            if (colon != std::string::npos)
                return line.substr(line.find_first_not_of(' ', colon + 1));
        }
    return "unknown";
}

} // namespace apps
