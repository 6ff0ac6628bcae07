// What the apps share besides their flags (apps/Flags.h) and reports (apps/Report.h): the exit
// codes, the checks of --seed and output folders, the parsing of the command line and the mapping
// of errors to exit codes, and the CPU's name for their reports.
#pragma once

#include <geometry/core/Error.h>

#include <CLI/CLI.hpp>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>

namespace apps {

inline constexpr int kExitInternalError = 1;
inline constexpr int kExitInputError = 2;

// --seed: parsed wider than the seed so that a negative or too large value gets this message,
// not a bare conversion error.
std::uint32_t checkSeed(std::int64_t seed);

// An output folder named by `flag` (e.g. "--out") can be created or written: it is a folder, or
// its nearest existing ancestor is a writable folder. Checked before any work, so that a mistake
// is bad input found at once, not an error after the rendering.
void checkOutputFolder(const char* flag, const std::filesystem::path& folder);

// A command-line parse error (the CLI11 exception's message) in the form of every other error:
// "PROGRAM: error: MESSAGE" and a hint; returns the bad-input exit code 2.
int reportParseError(const char* program, const std::exception& e);

// How parseCommandLine shows a parse error: in the form of every other error
// (reportParseError: penumbra-render, penumbra-bench) or as CLI11 prints it (penumbra-soak,
// penumbra-viewer).
enum class ParseErrorStyle { Prefixed, Cli11 };

// Parses the command line. Nothing when the program goes on; else the exit code main returns:
// 0 after --help (printed), 2 after a parse error (printed in `style`).
std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv, const char* program,
                                    ParseErrorStyle style);

// Runs `body` (the program once its flags are parsed) and returns its exit code, or maps what it
// throws: a geometry::InputError is bad input ("PROGRAM: error: MESSAGE", exit 2), any other
// std::exception an internal error ("PROGRAM: internal error: MESSAGE", exit 1). An app with
// errors of its own (a window that cannot open, an interrupt) catches them inside `body`.
template <class Body> int runMappingErrors(const char* program, Body&& body) {
    try {
        return body();
    } catch (const geometry::InputError& e) {
        std::fprintf(stderr, "%s: error: %s\n", program, e.what());
        return kExitInputError;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: internal error: %s\n", program, e.what());
        return kExitInternalError;
    }
}

// main after its flags are declared: parseCommandLine, then runMappingErrors(program, body).
template <class Body>
int runCommandLine(CLI::App& app, int argc, char** argv, const char* program, ParseErrorStyle style,
                   Body&& body) {
    if (const std::optional<int> exitCode = parseCommandLine(app, argc, argv, program, style))
        return *exitCode;
    return runMappingErrors(program, body);
}

// The CPU model from /proc/cpuinfo ("unknown" when it cannot be read), stated beside timings.
std::string cpuModel();

} // namespace apps
