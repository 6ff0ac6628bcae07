// penumbra-render: headless renderer (DESIGN.md §3 contract).
// - loads a scene JSON (or a .gltf/.glb: seen from its first glTF camera, or --camera N, lit by
//   the viewer's lamp for that view unless --scene-light; else framed automatically) and
//   validates every flag first: bad input exits with code 2 and writes nothing;
// - renders --frames frames with --method on a surfaceless EGL context (llvmpipe in CI);
// - writes image.png, visibility.pfm, position.pfm and report.json into --out;
// - with --compare FILE (a visibility.pfm of the same view, e.g. from --method reference) also
//   reports the error statistics of DESIGN.md §5 and writes error.png, a false-colour |ΔV| heat
//   map with its scale (geometry/reference/ErrorImage.h);
// - with --debug-view NAME image.png shows a debug view of the renderer (gpu/Renderer.h
//   DebugView) instead of the shaded image.
#include <apps/AppCommon.h>
#include <apps/Flags.h>
#include <apps/Report.h>
#include <geometry/core/Error.h>
#include <geometry/reference/ErrorImage.h>
#include <geometry/reference/ErrorStats.h>
#include <geometry/scene/ImageIO.h>
#include <geometry/scene/Scene.h>
#include <geometry/reference/Framing.h>
#include <gpu/gl/Context.h>
#include <gpu/Renderer.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using apps::median;

nlohmann::json errorJson(const geometry::ErrorStats& e) {
    return {{"pixels", e.pixels},         {"mismatched_coverage", e.mismatchedCoverage},
            {"mean_abs_err", e.meanAbs},  {"rmse", e.rmse},
            {"p99_err", e.p99},           {"max_err", e.max},
            {"bad_pixel_pct", e.badPixelPct}};
}

struct Options {
    std::string scenePath;
    std::string methodName;
    std::string size = "512x512";
    std::string outDir = "out";
    int samples = 1024;
    int frames = 1;
    int warmup = 0;       // --warmup N: frames rendered first and left out of every time
    std::uint32_t seed = 1;
    std::string comparePath;
    float errorScale = geometry::kDefaultErrorScale;
    std::vector<std::string> parameters; // --param NAME=VALUE, in the order given
    std::optional<int> camera;           // --camera N: index into the glTF cameras
    bool sceneLight = false;             // --scene-light: no lamp at a glTF camera
    bool quiet = false;
    float simplify = 0.0f; // --simplify E (apps/Flags.h)
    std::string debugView = "shaded"; // what image.png shows (gpu::debugViews())
    int debugGroup = 0;
};

// A resolved parameter's value for report.json: a number when it is an integer.
nlohmann::json parameterJson(const std::string& value) {
    static const std::regex integer(R"(-?\d{1,9})");
    if (std::regex_match(value, integer)) return std::stoi(value);
    return value;
}

int run(const Options& opt) {
    // Everything that can be wrong with the input is checked before anything is written.
    apps::checkOutputFolder("--out", opt.outDir);
    const gpu::MethodInfo& method = gpu::findMethod(opt.methodName);
    const std::vector<gpu::ParameterValue> given = apps::parseParameters(opt.parameters);
    const std::vector<gpu::ParameterValue> parameters = gpu::resolveParameters(method, given);
    const auto [width, height] = apps::parseSize(opt.size, "512x512");
    apps::checkSamples(opt.samples);
    if (opt.frames < 1 || opt.frames > 10000)
        throw geometry::InputError("--frames must be between 1 and 10000");
    if (opt.warmup < 0 || opt.warmup > 10000)
        throw geometry::InputError("--warmup must be between 0 and 10000");
    if (!(opt.errorScale > 0.0f && opt.errorScale <= 1.0f))
        throw geometry::InputError("--error-scale must be in (0, 1]");
    const gpu::DebugViewInfo& debugView = gpu::findDebugView(opt.debugView);
    // The error view's reference gains RenderSettings::referenceSamplesPerFrame light samples a
    // frame: render until it is complete.
    const int perFrame = gpu::RenderSettings{}.referenceSamplesPerFrame;
    const int frames = debugView.view == gpu::DebugView::ErrorHeatMap
                           ? std::max(opt.frames, (opt.samples + perFrame - 1) / perFrame)
                           : opt.frames;

    std::optional<geometry::FloatImage> compareTo;
    if (!opt.comparePath.empty()) {
        try {
            compareTo = geometry::readPfm(opt.comparePath);
        } catch (const geometry::InputError& e) {
            throw geometry::InputError(std::string("--compare: ") + e.what());
        }
        if (compareTo->width != width || compareTo->height != height || compareTo->channels != 1)
            throw geometry::InputError("--compare: " + opt.comparePath + " is " +
                                       std::to_string(compareTo->width) + "x" +
                                       std::to_string(compareTo->height) + "x" +
                                       std::to_string(compareTo->channels) +
                                       ", expected a 1-channel " + std::to_string(width) + "x" +
                                           std::to_string(height) + " visibility map");
    }

    auto t0 = std::chrono::steady_clock::now();
    geometry::Scene scene = geometry::loadScene(opt.scenePath);
    if (opt.camera) {
        try {
            geometry::selectCamera(scene, *opt.camera);
        } catch (const geometry::InputError& e) {
            throw geometry::InputError(std::string("--camera: ") + e.what());
        }
    }
    // At a glTF camera, the viewer's lamp for the view (as the viewer and the bench light it).
    const std::string lightSource = geometry::lightAtView(scene, opt.sceneLight);
    // Under the final light: the bounds follow from its size and distance.
    const apps::SimplifyApplied simplified = apps::applySimplify(scene, opt.simplify);
    const double loadMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    gpu::EglContext context;
    const gpu::ContextInfo info = context.info();
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    t0 = std::chrono::steady_clock::now();
    gpu::Renderer renderer(scene, shaders);
    const double setupMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    gpu::RenderSettings settings;
    settings.method = std::string(method.name);
    settings.width = width;
    settings.height = height;
    settings.samples = opt.samples;
    settings.seed = opt.seed;
    settings.parameters = given;
    settings.debugView = debugView.view;
    settings.debugGroup = opt.debugGroup;
    settings.errorScale = opt.errorScale;
    if (!opt.quiet && method.name == "reference")
        settings.progress = [tty = isatty(fileno(stderr)) != 0](int done, int total) {
            // One line per update when logged (CI), an updating line on a terminal.
            std::fprintf(stderr, "%s  reference: %d/%d light samples%s", tty ? "\r" : "", done,
                         total, tty && done < total ? "" : "\n");
        };
    if (!opt.quiet && (method.name == "pdsm" || method.name == "deep-sm"))
        settings.progress = [tty = isatty(fileno(stderr)) != 0, last = -1,
                             what = method.name == "pdsm" ? "pdsm: deep map"
                                                          : "deep-sm: deep maps"](
                                int done, int total) mutable {
            // The deep map's rows as they are built: every tenth when logged, all on a terminal.
            const int tenth = total > 0 ? 10 * done / total : 10;
            if (!tty && tenth == last) return;
            last = tenth;
            std::fprintf(stderr, "%s  %s %d/%d rows%s", tty ? "\r" : "", what, done, total,
                         tty && done < total ? "" : "\n");
        };

    std::vector<double> frameMs;
    std::map<std::string, std::vector<double>> gpuMs, cpuMs;
    std::vector<std::string> gpuOrder, cpuOrder;
    gpu::FrameStats last;
    // Per name, one time per frame: a pass run twice in a frame (a composite's "compose") is
    // summed, and a pass or stage a frame skipped (maps kept while the light is still, a fit
    // done once) took 0 ms in it, so the medians are per frame rendered.
    const auto record = [frames](auto& times, std::vector<std::string>& order,
                                 const std::string& name, double ms, int frame) {
        auto [it, added] = times.try_emplace(name, std::vector<double>(frames, 0.0));
        if (added) order.push_back(name);
        it->second[static_cast<std::size_t>(frame)] += ms;
    };
    for (int f = -opt.warmup; f < frames; ++f) {
        last = renderer.renderFrame(settings);
        if (f < 0) continue; // a warm-up frame
        frameMs.push_back(last.frameMs);
        for (const auto& p : last.gpu) record(gpuMs, gpuOrder, p.name, p.ms, f);
        for (const auto& c : last.cpu) record(cpuMs, cpuOrder, c.name, c.ms, f);
    }

    const geometry::FloatImage visibility = renderer.visibility();
    const geometry::FloatImage position = renderer.position();
    const std::vector<std::uint8_t> image = renderer.imageRgba8();

    nlohmann::json report;
    report["method"] = method.name;
    report["scene"] = opt.scenePath;
    report["parameters"] = {{"samples", method.usesSamples ? opt.samples : 1},
                            {"seed", opt.seed},
                            {"frames", frames},
                            {"warmup", opt.warmup}};
    for (const gpu::ParameterValue& p : parameters) // every one the method has, as used
        report["parameters"][p.name] = parameterJson(p.value);
    report["size"] = {width, height};
    // The view actually rendered (camera_source: the scene JSON, a glTF camera or the framing).
    report["camera"] = {{"eye", apps::vec3Json(scene.camera.eye)},
                        {"target", apps::vec3Json(scene.camera.target)},
                        {"up", apps::vec3Json(scene.camera.up)},
                        {"fov_y_deg", scene.camera.fovYDeg}};
    report["camera_source"] = scene.cameraSource;
    report["light_source"] = lightSource;
    report["cameras"] = scene.cameras.size();
    report["light"] = {{"center", apps::vec3Json(scene.light.center)},
                       {"u", apps::vec3Json(scene.light.u)},
                       {"v", apps::vec3Json(scene.light.v)}};
    if (debugView.view != gpu::DebugView::Shaded)
        report["debug_view"] = {{"name", debugView.name}, {"note", last.debugNote}};
    report["gl_renderer"] = info.renderer;
    report["gl_version"] = info.version;
    report["triangles"] = last.triangles;
    report["silhouette_edges"] = last.silhouetteEdges;
    nlohmann::json objects = nlohmann::json::array();
    for (const auto& o : renderer.objects()) {
        nlohmann::json j = {{"name", o.name}, {"triangles", o.triangles}, {"casts", o.casts}};
        if (o.casts)
            j.update({{"topology", geometry::toString(o.manifoldness)},
                      {"welded_vertices", o.topology.vertices},
                      {"edges", o.topology.edges},
                      {"boundary_edges", o.topology.boundaryEdges},
                      {"non_manifold_edges", o.topology.nonManifoldEdges},
                      {"degenerate_triangles", o.topology.degenerateTriangles},
                      {"duplicate_triangles", o.topology.duplicateTriangles}});
        objects.push_back(std::move(j));
    }
    // The path a choosing method (auto) gave each casting object, and why.
    for (const auto& choice : last.objectChoices)
        if (choice.object < objects.size())
            objects[choice.object].update(
                {{"shadow_path", choice.path}, {"shadow_path_reason", choice.reason}});
    report["objects"] = std::move(objects);
    report["silhouette_groups"] = last.silhouetteGroups;
    report["silhouette_upload_bytes"] = last.silhouetteUploadBytes;
    // Wedges drawn this frame (0 for methods without wedges); per-kind counts in "counters".
    double wedges = 0.0;
    nlohmann::json counters = nlohmann::json::object();
    // Limitations a method counted this frame that make its picture wrong somewhere: said on
    // stderr and in report.json's "warnings", not only as a counter.
    nlohmann::json warnings = nlohmann::json::array();
    for (const auto& c : last.counters) {
        counters[c.name] = c.value;
        if (c.name == "wedges") wedges = c.value;
        if (c.name == "sample_maps_clipped" && c.value > 0.0)
            warnings.push_back("sample-maps: casters reach the light's plane or lie beyond the "
                               "maps' 71.6-degree frustum (sample_maps_clipped); what they hide "
                               "from the samples that cannot see them is drawn lit");
        if (c.name == "linear_light_sm_clipped" && c.value > 0.0)
            warnings.push_back("linear-light-sm: casters reach the light's plane or lie beyond "
                               "the end points' maps' 71.6-degree frustum "
                               "(linear_light_sm_clipped); what they hide from the end points "
                               "that cannot see them is drawn lit");
        if (c.name == "pdsm_clipped" && c.value > 0.0)
            warnings.push_back("pdsm: casters reach the light's plane or lie beyond the maps' "
                               "71.6-degree frustum (pdsm_clipped); what they hide from the "
                               "samples that cannot see them, and receivers outside the deep map "
                               "(pdsm_pixels_outside), are drawn lit");
    }
    for (const auto& w : warnings)
        std::fprintf(stderr, "penumbra-render: warning: %s\n", w.get<std::string>().c_str());
    report["warnings"] = std::move(warnings);
    report["wedges"] = wedges;
    report["simplify"] = apps::simplifyJson(simplified);
    report["counters"] = std::move(counters);
    report["shadow_volume_triangles"] = last.volumeTriangles;
    nlohmann::json gpuJson = nlohmann::json::object(), cpuJson = nlohmann::json::object();
    for (const auto& name : gpuOrder) gpuJson[name] = median(gpuMs[name]);
    for (const auto& name : cpuOrder) cpuJson[name] = median(cpuMs[name]);
    cpuJson["scene-load"] = loadMs;
    cpuJson["renderer-setup"] = setupMs;
    report["gpu_ms"] = gpuJson;
    report["cpu_ms"] = cpuJson;
    report["frame_ms"] = median(frameMs);
    report["frame_ms_each"] = frameMs; // in order, after the warm-up
    report["timing_note"] = "medians over frames of each pass's time in the frame (summed "
                            "where it ran twice, 0 ms where it was skipped); gpu_ms from GL "
                            "timestamp queries on the renderer named in gl_renderer (software "
                            "on llvmpipe)";
    std::optional<geometry::ErrorStats> error;
    if (compareTo) {
        error = geometry::compareVisibility(visibility.data, compareTo->data);
        report["compare"] = opt.comparePath;
        report["error"] = errorJson(*error);
        report["error_image"] = {{"file", "error.png"}, {"scale_max", opt.errorScale}};
    }

    fs::create_directories(opt.outDir);
    const fs::path out(opt.outDir);
    geometry::writePng(out / "image.png", width, height, 4, image.data());
    geometry::writePfm(out / "visibility.pfm", visibility);
    geometry::writePfm(out / "position.pfm", position);
    if (compareTo) {
        const geometry::RgbImage heat = geometry::errorHeatMap(visibility.data, compareTo->data,
                                                               width, height, opt.errorScale);
        geometry::writePng(out / "error.png", heat.width, heat.height, 3, heat.rgb.data());
    }
    apps::writeJsonFile(out / "report.json", report);

    if (!opt.quiet) {
        std::printf("%s: %s, %dx%d, %zu triangles, %zu silhouette edges\n", opt.scenePath.c_str(),
                    std::string(method.name).c_str(), width, height, last.triangles, last.silhouetteEdges);
        std::printf("  camera: %s", scene.cameraSource.c_str());
        if (!scene.cameras.empty()) std::printf(" (of %zu glTF cameras)", scene.cameras.size());
        if (scene.skippedCameras > 0)
            std::printf(" (%d orthographic glTF camera%s skipped)", scene.skippedCameras,
                        scene.skippedCameras == 1 ? "" : "s");
        std::printf("\n");
        std::printf("  light: %s\n", lightSource.c_str());
        if (simplified.visibilityError > 0.0f)
            std::printf("  %s\n", apps::simplifySummary(simplified).c_str());
        std::printf("  renderer: %s\n", info.renderer.c_str());
        // Where a method chose per object (auto), or left alpha-tested ones to auto's alpha
        // path: one line per object.
        for (const auto& choice : last.objectChoices)
            std::printf("  object '%s': %s (%s)\n", scene.objects[choice.object].name.c_str(),
                        choice.path.c_str(), choice.reason.c_str());
        if (!last.debugNote.empty()) std::printf("  %s\n", last.debugNote.c_str());
        std::printf("  frame %.2f ms (median of %d)", median(frameMs), frames);
        for (const auto& name : gpuOrder)
            std::printf(", %s %.2f", name.c_str(), median(gpuMs[name]));
        std::printf(" (GPU ms)\n");
        if (error)
            std::printf("  error vs %s: mean %.4f, rmse %.4f, p99 %.4f, max %.4f, "
                        "%.2f%% pixels > 0.05\n",
                        opt.comparePath.c_str(), error->meanAbs, error->rmse, error->p99,
                        error->max, error->badPixelPct);
        std::printf("  wrote %s/{image.png, visibility.pfm, position.pfm, report.json%s}\n",
                    opt.outDir.c_str(), error ? ", error.png" : "");
    }
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"penumbra-render: headless soft-shadow renderer (surfaceless EGL)"};
    Options opt;
    std::string methods;
    for (const gpu::MethodInfo& m : gpu::methodTable()) {
        methods += "\n    " + std::string(m.name) + (m.implemented() ? "" : " (not implemented yet)") +
                   ": " + std::string(m.summary);
        for (const gpu::MethodParameter& p : m.parameters) {
            std::string values;
            for (std::string_view v : p.values) {
                if (!values.empty()) values += '|';
                values += v;
            }
            methods += "\n        --param " + std::string(p.name) + "=" + values + " (default " +
                       std::string(p.defaultValue) + "): " + std::string(p.help);
        }
    }
    app.add_option("--scene", opt.scenePath,
                   "scene JSON, or a .gltf/.glb: seen from its first perspective glTF camera, "
                   "else framed automatically")
        ->required();
    apps::addMethodOption(app, opt.methodName, "visibility method, one of:" + methods)->required();
    apps::addSizeOption(app, opt.size);
    app.add_option("--out", opt.outDir, "output directory")->capture_default_str();
    apps::addSamplesOption(app, opt.samples, "light samples per pixel (reference, raytrace)");
    app.add_option("--frames", opt.frames, "frames to render; times are medians")
        ->capture_default_str();
    app.add_option("--warmup", opt.warmup,
                   "frames rendered before --frames and left out of every time (the first "
                   "builds what a method precomputes; on llvmpipe the next few run slower)")
        ->capture_default_str();
    std::int64_t seed = opt.seed; // checked by apps::checkSeed
    app.add_option("--seed", seed, "sample pattern seed (reference, raytrace)")
        ->capture_default_str();
    app.add_option("--compare", opt.comparePath,
                   "reference visibility.pfm of the same view: report the error against it");
    app.add_option("--error-scale", opt.errorScale,
                   "with --compare: the |error| at the top of error.png's colour scale")
        ->capture_default_str();
    apps::addParamOption(app, opt.parameters, "a parameter of the method, NAME=VALUE (repeatable; "
                                              "listed under --method)");
    app.add_option("--camera", opt.camera,
                   "with a .gltf/.glb: view from its glTF camera N (0 = the first, the default; "
                   "report.json camera_source names it); lit by the viewer's lamp for that view "
                   "(a small light under the ceiling ahead; report.json light_source)");
    app.add_flag("--scene-light", opt.sceneLight,
                 "at a glTF camera, keep the file's framed light instead of the viewer's lamp");
    std::string views;
    for (const gpu::DebugViewInfo& v : gpu::debugViews())
        views += "\n    " + std::string(v.name) + ": " + std::string(v.help);
    app.add_option("--debug-view", opt.debugView,
                   "what image.png shows (error: renders at least ceil(samples / 16) frames, "
                   "until its reference is complete; --error-scale sets its scale), one of:" +
                       views)
        ->capture_default_str();
    app.add_option("--debug-group", opt.debugGroup,
                   "with --debug-view group-parts: the silhouette group shown (wrapped)")
        ->capture_default_str();
    apps::addSimplifyOption(app, opt.simplify);
    app.add_flag("--quiet", opt.quiet, "print nothing on success");
    return apps::runCommandLine(app, argc, argv, "penumbra-render",
                                apps::ParseErrorStyle::Prefixed, [&] {
        opt.seed = apps::checkSeed(seed);
        return run(opt);
    });
}
