#include <apps/Flags.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <geometry/core/Error.h>

#include <regex>

namespace apps {

CLI::Option* addSizeOption(CLI::App& app, std::string& size, const std::string& help) {
    return app.add_option("--size", size, help)->capture_default_str();
}

std::pair<int, int> parseSize(const std::string& s, const char* example) {
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
    if (w < kMinImageSide || h < kMinImageSide || w > kMaxImageSide || h > kMaxImageSide)
        throw geometry::InputError("--size: each side must be between " +
                                   std::to_string(kMinImageSide) + " and " +
                                   std::to_string(kMaxImageSide) + ", got '" + s + "'");
    return {w, h};
}

CLI::Option* addMethodOption(CLI::App& app, std::string& method, const std::string& help) {
    return app.add_option("--method", method, help);
}

CLI::Option* addMethodOption(CLI::App& app, std::vector<std::string>& methods,
                             const std::string& help) {
    return app.add_option("--method", methods, help);
}

CLI::Option* addParamOption(CLI::App& app, std::vector<std::string>& parameters,
                            const std::string& help) {
    return app.add_option("--param", parameters, help)->allow_extra_args(false);
}

std::vector<gpu::ParameterValue> parseParameters(const std::vector<std::string>& texts) {
    std::vector<gpu::ParameterValue> given;
    for (const std::string& text : texts)
        given.push_back(gpu::parseParameter(text));
    return given;
}

CLI::Option* addSamplesOption(CLI::App& app, int& samples, const std::string& help) {
    return app.add_option("--samples", samples, help)->capture_default_str();
}

void checkSamples(int samples, const char* flag) {
    if (samples < kMinSamples || samples > kMaxSamples)
        throw geometry::InputError(std::string(flag) + " must be between " +
                                   std::to_string(kMinSamples) + " and " +
                                   std::to_string(kMaxSamples));
}

CLI::Option* addSimplifyOption(CLI::App& app, float& visibilityError) {
    return app
        .add_option("--simplify", visibilityError,
                    "replace finely tessellated meshes by simplified stand-ins whose visibility "
                    "differs by about E at most (more where a shadow nears its caster's contact; "
                    "0 = off, up to 0.25; untextured, single-material, manifold meshes only; "
                    "docs/benchmarks.md, Simplified stand-ins)")
        ->type_name("E")
        ->capture_default_str();
}

SimplifyApplied applySimplify(geometry::Scene& scene, float visibilityError) {
    if (!std::isfinite(visibilityError) || visibilityError < 0.0f || visibilityError > kMaxSimplify)
        throw geometry::InputError("--simplify must be between 0 (off) and 0.25 (got " +
                                   std::to_string(visibilityError) + ")");
    SimplifyApplied applied;
    applied.visibilityError = visibilityError;
    if (visibilityError == 0.0f) return applied;
    const auto t0 = std::chrono::steady_clock::now();
    applied.stats = geometry::simplifyScene(scene, visibilityError);
    // The stand-ins move surfaces by up to E times half the light's side: one that now reaches
    // the light is refused as the original would have been.
    geometry::validateLight(scene, scene.light, "light (with --simplify's stand-ins)");
    applied.ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return applied;
}

std::string simplifySummary(const SimplifyApplied& a) {
    char line[256];
    std::snprintf(line, sizeof line,
                  "simplify: visibility error about %g: %zu meshes, %zu -> %zu triangles in "
                  "%.0f ms; %zu left as they were",
                  double(a.visibilityError), a.stats.meshes, a.stats.trianglesBefore,
                  a.stats.trianglesAfter, a.ms, a.stats.skipped);
    std::string s = line;
    if (a.stats.skipped > 0) s += " (first: " + a.stats.firstSkipReason + ")";
    return s;
}

nlohmann::json simplifyJson(const SimplifyApplied& a) {
    return {{"visibility_error", a.visibilityError},
            {"meshes", a.stats.meshes},
            {"triangles_before", a.stats.trianglesBefore},
            {"triangles_after", a.stats.trianglesAfter},
            {"skipped", a.stats.skipped},
            {"ms", a.ms}};
}

} // namespace apps
