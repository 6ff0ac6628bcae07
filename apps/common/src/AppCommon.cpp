#include <apps/AppCommon.h>

#include <unistd.h>

#include <fstream>
#include <system_error>

namespace apps {

std::uint32_t checkSeed(std::int64_t seed) {
    if (seed < 0 || seed > std::int64_t(UINT32_MAX))
        throw geometry::InputError("--seed must be between 0 and 4294967295, got " +
                                   std::to_string(seed));
    return std::uint32_t(seed);
}

void checkOutputFolder(const char* flag, const std::filesystem::path& folder) {
    namespace fs = std::filesystem;
    const std::string name = std::string(flag) + ": '" + folder.string() + "'";
    if (folder.empty()) throw geometry::InputError(std::string(flag) + ": empty folder name");
    std::error_code ec;
    if (fs::exists(folder, ec) && !fs::is_directory(folder, ec))
        throw geometry::InputError(name + " exists and is not a folder");
    fs::path existing = fs::absolute(folder, ec);
    while (!existing.empty() && !fs::exists(existing, ec) && existing.has_relative_path()) {
        // A symbolic link to nothing: creating the folder would fail, after the work.
        if (fs::is_symlink(fs::symlink_status(existing, ec)))
            throw geometry::InputError(name + " cannot be created: '" + existing.string() +
                                       "' is a symbolic link to '" +
                                       fs::read_symlink(existing, ec).string() +
                                       "', which does not exist");
        existing = existing.parent_path();
    }
    if (!fs::is_directory(existing, ec))
        throw geometry::InputError(name + " cannot be created: '" + existing.string() +
                                   "' is not a folder");
    if (access(existing.c_str(), W_OK | X_OK) != 0)
        throw geometry::InputError(name + " cannot be written: no write permission in '" +
                                   existing.string() + "'");
}

int reportParseError(const char* program, const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\nRun with --help for more information.\n", program,
                 e.what());
    return kExitInputError;
}

std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv, const char* program,
                                    ParseErrorStyle style) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e); // --help
        if (style == ParseErrorStyle::Prefixed) return reportParseError(program, e);
        app.exit(e);
        return kExitInputError;
    }
    return std::nullopt;
}

std::string cpuModel() {
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
