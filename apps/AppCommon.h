// What the apps share: --size parsing and the CPU's name for their reports.
#pragma once

#include <geometry/Error.h>

#include <fstream>
#include <regex>
#include <string>
#include <utility>

namespace apps {

// --size WIDTHxHEIGHT: the format, then each side in [minSide, maxSide]; a geometry::InputError
// naming the flag otherwise (bad input: exit 2).
inline std::pair<int, int> parseSize(const std::string& s, int minSide, int maxSide,
                                     const char* example) {
    static const std::regex re(R"((\d{1,5})x(\d{1,5}))");
    std::smatch m;
    if (!std::regex_match(s, m, re))
        throw geometry::InputError(std::string("--size: expected WIDTHxHEIGHT (e.g. ") + example +
                                   "), got '" + s + "'");
    const int w = std::stoi(m[1]), h = std::stoi(m[2]);
    if (w < minSide || h < minSide || w > maxSide || h > maxSide)
        throw geometry::InputError("--size: each side must be between " + std::to_string(minSide) +
                                   " and " + std::to_string(maxSide) + ", got '" + s + "'");
    return {w, h};
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
