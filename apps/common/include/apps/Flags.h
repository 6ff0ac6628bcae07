// The flags every app that renders declares alike: --size, --method, --param, --samples and
// --simplify, each declared once here with one set of limits, and the checks of their values
// (bad input throws a geometry::InputError naming the flag: exit 2).
//
// The limits are the engine's:
// - --size: each side 1 to 16384. 16384 is the GL_MAX_TEXTURE_SIZE every OpenGL 4.5
//   implementation must offer (the spec's minimum, and llvmpipe's value), and the renderer itself
//   accepts 1x1; a size within the limit that the GL implementation cannot hold is refused by the
//   renderer with the largest square that fits.
// - --samples: 1 to 65536 light samples per pixel. At 65536 the Monte Carlo error of V is below
//   0.002 (1 / (2 sqrt N)), under the 1/255 step of an 8-bit image, so more cannot change what is
//   shown, while every sample is a pass of `reference` (2^20, penumbra-render's old bound, was
//   hours of rendering); the viewer and the bench's --truth-samples had 65536 already.
// An app that needs narrower bounds (the viewer's window) checks them itself, with its own message.
#pragma once

#include <geometry/scene/Scene.h>
#include <geometry/shadow/Simplify.h>
#include <gpu/Methods.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace apps {

inline constexpr int kMinImageSide = 1;
inline constexpr int kMaxImageSide = 16384;
inline constexpr int kMinSamples = 1;
inline constexpr int kMaxSamples = 65536;

// --size WIDTHxHEIGHT (the value's default shown in --help).
CLI::Option* addSizeOption(CLI::App& app, std::string& size,
                           const std::string& help = "image size WIDTHxHEIGHT");
// --size: the format, then each side in [kMinImageSide, kMaxImageSide]. `example` is a valid
// size for the message (e.g. the app's default).
std::pair<int, int> parseSize(const std::string& size, const char* example);

// --method NAME (one method), or repeated (a list). Checked by gpu::findMethod.
CLI::Option* addMethodOption(CLI::App& app, std::string& method, const std::string& help);
CLI::Option* addMethodOption(CLI::App& app, std::vector<std::string>& methods,
                             const std::string& help);

// --param NAME=VALUE, repeatable, in the order given; one value per occurrence.
CLI::Option* addParamOption(CLI::App& app, std::vector<std::string>& parameters,
                            const std::string& help = "a parameter of the method, NAME=VALUE "
                                                      "(repeatable)");
// Each --param text as NAME=VALUE (gpu::parseParameter), in the order given.
std::vector<gpu::ParameterValue> parseParameters(const std::vector<std::string>& texts);

// --samples N (the value's default shown in --help).
CLI::Option* addSamplesOption(CLI::App& app, int& samples,
                              const std::string& help = "light samples of reference and raytrace");
// A sample count in [kMinSamples, kMaxSamples]; `flag` names it in the message ("--samples",
// "--truth-samples").
void checkSamples(int samples, const char* flag = "--samples");

// --simplify E: every mesh that can be is replaced by a simplified stand-in whose visibility
// differs by about E at most (geometry/shadow/Simplify.h: positions within E times half the
// light's smaller side, normals within E times the angle the light subtends); 0 (the default)
// keeps the scene as it is. E in [0, kMaxSimplify].
inline constexpr float kMaxSimplify = 0.25f;
CLI::Option* addSimplifyOption(CLI::App& app, float& visibilityError);

struct SimplifyApplied {
    float visibilityError = 0.0f; // as given; 0 = off
    geometry::SimplifyStats stats;
    double ms = 0.0;
};
// Applies --simplify to a loaded scene under its final light (after --camera picked the lamp).
// Throws geometry::InputError naming the flag for a value out of range.
SimplifyApplied applySimplify(geometry::Scene& scene, float visibilityError);
// One line for stdout: what was simplified, how much, in how long, and what was left alone.
std::string simplifySummary(const SimplifyApplied& applied);
// report.json's "simplify" object (penumbra-render, the viewer's --report).
nlohmann::json simplifyJson(const SimplifyApplied& applied);

} // namespace apps
