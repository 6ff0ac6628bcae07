// penumbra-bench: scenes × methods × parameters, speed against accuracy (DESIGN.md §3, §5).
//
// All runs share one process and one surfaceless EGL context; each scene is loaded once and
// rendered by one Renderer. A .gltf/.glb level is measured from its glTF (spawn) cameras
// (--cameras, default the first), each lit by the viewer's lamp for its view. Per view and light
// scale:
// - the truth (`reference`, or `raytrace` with --truth) of the same view, once, and along the
//   light path when flicker is measured;
// - `hard` first (the denominator of frame_over_hard), then every requested run: warm-up frames,
//   timed frames (medians), the error statistics against the truth, and the flicker along the path
//   (the light's centre moved along its u axis, --sweep half-widths each way, --flicker-steps
//   steps; §5's mean over consecutive frames of mean |ΔV − ΔV_truth|).
// Rows go to results.csv as they finish (a valid CSV at every moment: Ctrl-C keeps the runs done),
// results.json gets the same plus the machine, and chart.png is drawn by apps/bench/chart.py with
// Debian's matplotlib. Input is checked before any work: bad input exits 2, nothing written.
#include <apps/AppCommon.h>
#include <apps/Flags.h>
#include <apps/Report.h>
#include <geometry/core/Error.h>
#include <geometry/reference/ErrorImage.h>
#include <geometry/reference/ErrorStats.h>
#include <geometry/scene/ImageIO.h>
#include <geometry/scene/Scene.h>
#include <geometry/reference/Framing.h>
#include <geometry/reference/RayTracer.h>
#include <gpu/gl/Context.h>
#include <gpu/gl/Debug.h>
#include <gpu/Renderer.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

constexpr int kExitInterrupted = 130;

std::atomic<bool> gInterrupted{false};
extern "C" void onInterrupt(int) { gInterrupted = true; }

struct Interrupted {};
void checkInterrupt() {
    if (gInterrupted) throw Interrupted{};
}

using apps::median; // NaN (an empty cell) when nothing was timed

std::vector<std::string> splitList(const std::string& s, char sep = ',') {
    std::vector<std::string> out;
    std::stringstream in(s);
    std::string item;
    while (std::getline(in, item, sep))
        if (!item.empty()) out.push_back(item);
    return out;
}

std::string csvField(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

std::string number(double x, int precision = 6) {
    if (!std::isfinite(x)) return ""; // an empty cell: not measured
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", precision, x);
    return buf;
}

// ---- what to run ------------------------------------------------------------------------------

struct Options {
    std::vector<std::string> inputs;
    std::string methods = "all";
    std::vector<std::string> sweeps; // METHOD:NAME=V1,V2
    std::string lightScales = "1";
    std::string size = "256x256";
    std::string truth = "reference";
    int truthSamples = 1024;
    int frames = 5;
    int warmup = 1;
    int flickerSteps = 8;
    float sweep = 1.0f;
    std::uint32_t seed = 1;
    std::string outDir = "out/bench";
    std::string cameras = "0"; // of a .gltf/.glb: framed, all, or N,M,...
    bool saveImages = false;
    bool noChart = false;
};

struct RunSpec {
    const gpu::MethodInfo* method = nullptr;
    std::vector<gpu::ParameterValue> given; // swept parameters (the rest default)
    int samples = 0;                        // usesSamples methods
};

// "NAME=V1,V2" per method, expanded into the cartesian product of the swept values.
std::vector<RunSpec> expandRuns(const std::vector<std::string>& methodNames,
                                const std::vector<std::string>& sweepTexts, int defaultSamples) {
    std::map<std::string, std::vector<std::pair<std::string, std::vector<std::string>>>> sweeps;
    for (const std::string& text : sweepTexts) {
        static const std::regex re(R"(([a-z0-9-]+):([a-z_]+)=([^=]+))");
        std::smatch m;
        if (!std::regex_match(text, m, re))
            throw geometry::InputError("--sweep: expected METHOD:NAME=V1,V2,... (e.g. "
                                       "wedges-blend:parts=1,4,8), got '" + text + "'");
        const gpu::MethodInfo& method = gpu::findMethod(m[1].str());
        if (std::find(methodNames.begin(), methodNames.end(), m[1].str()) == methodNames.end())
            throw geometry::InputError("--sweep " + text + ": method '" + m[1].str() +
                                       "' is not among --methods");
        const std::vector<std::string> values = splitList(m[3].str());
        if (values.empty()) throw geometry::InputError("--sweep " + text + ": no values");
        const std::string name = m[2].str();
        // samples: the reference methods' sample count (RenderSettings::samples), or a
        // parameter of that name the method declares (wedges-bitmask's).
        const bool hasSamplesParameter =
            std::any_of(method.parameters.begin(), method.parameters.end(),
                        [](const gpu::MethodParameter& p) { return p.name == "samples"; });
        if (name == "samples" && !hasSamplesParameter) {
            if (!method.usesSamples)
                throw geometry::InputError("--sweep " + text + ": '" + m[1].str() +
                                           "' takes no light samples");
            for (const std::string& v : values)
                if (!std::regex_match(v, std::regex(R"(\d{1,7})")) ||
                    std::stoi(v) < apps::kMinSamples || std::stoi(v) > apps::kMaxSamples)
                    throw geometry::InputError("--sweep " + text + ": '" + v +
                                               "' is not a sample count (" +
                                               std::to_string(apps::kMinSamples) + " to " +
                                               std::to_string(apps::kMaxSamples) + ")");
        } else {
            for (const std::string& v : values) { // checked against the method table now
                const std::vector<gpu::ParameterValue> one{{name, v}};
                gpu::resolveParameters(method, one);
            }
        }
        for (const auto& [existing, _] : sweeps[m[1].str()])
            if (existing == name)
                throw geometry::InputError("--sweep: " + m[1].str() + ":" + name + " given twice");
        sweeps[m[1].str()].push_back({name, values});
    }
    std::vector<RunSpec> runs;
    for (const std::string& name : methodNames) {
        const gpu::MethodInfo& method = gpu::findMethod(name);
        std::vector<RunSpec> partial{RunSpec{&method, {}, defaultSamples}};
        for (const auto& [param, values] : sweeps[name]) {
            std::vector<RunSpec> next;
            for (const RunSpec& r : partial)
                for (const std::string& v : values) {
                    RunSpec copy = r;
                    if (param == "samples" && method.usesSamples)
                        copy.samples = std::stoi(v);
                    else
                        copy.given.push_back({param, v});
                    next.push_back(copy);
                }
            partial = std::move(next);
        }
        runs.insert(runs.end(), partial.begin(), partial.end());
    }
    return runs;
}

std::vector<std::string> resolveMethods(const std::string& list) {
    std::vector<std::string> names;
    if (list == "all") {
        // Every implemented real-time method; the truth methods only when named.
        for (const gpu::MethodInfo& m : gpu::methodTable())
            if (m.implemented() && !m.usesSamples) names.emplace_back(m.name);
        return names;
    }
    for (const std::string& name : splitList(list)) {
        gpu::findMethod(name); // unknown or not implemented: InputError naming the others
        if (std::find(names.begin(), names.end(), name) != names.end())
            throw geometry::InputError("--methods: '" + name + "' given twice");
        names.push_back(name);
    }
    if (names.empty()) throw geometry::InputError("--methods: no method given");
    return names;
}

std::vector<fs::path> expandScenes(const std::vector<std::string>& inputs) {
    std::vector<fs::path> scenes;
    auto isScene = [](const fs::path& p) {
        const std::string ext = p.extension().string();
        return ext == ".json" || ext == ".gltf" || ext == ".glb";
    };
    for (const std::string& input : inputs) {
        std::error_code ec;
        if (fs::is_directory(input, ec)) {
            // A folder of scene JSONs (their .gltf meshes beside them are not scenes), or else
            // a folder of levels.
            std::vector<fs::path> json, gltf;
            for (const auto& entry : fs::directory_iterator(input))
                if (entry.is_regular_file() && isScene(entry.path()))
                    (entry.path().extension() == ".json" ? json : gltf).push_back(entry.path());
            std::vector<fs::path> found = json.empty() ? gltf : json;
            std::sort(found.begin(), found.end());
            if (found.empty())
                throw geometry::InputError(input + ": folder has no .json/.gltf/.glb scene");
            scenes.insert(scenes.end(), found.begin(), found.end());
        } else if (fs::is_regular_file(input, ec)) {
            if (!isScene(input))
                throw geometry::InputError(input + ": not a scene (.json, .gltf or .glb)");
            scenes.emplace_back(input);
        } else {
            throw geometry::InputError(input + ": no such file or folder");
        }
    }
    if (scenes.empty()) throw geometry::InputError("no scenes given");
    return scenes;
}

// ---- one run ----------------------------------------------------------------------------------

struct Row {
    std::string scene, method, params;
    double gpuMs = NAN, cpuMs = NAN, frameMs = NAN;
    geometry::ErrorStats error;
    bool haveError = false;
    double flicker = NAN;
    double lightScale = 1.0;
    int width = 0, height = 0;
    double frameOverHard = NAN;
    std::string truth;
    int truthSamples = 0;
    std::size_t nanPixels = 0, outOfRange = 0, glErrors = 0;
    std::string status = "ok";
};

const char* kCsvHeader =
    "scene,method,params,gpu_ms,cpu_ms,frame_ms,mean_abs_err,rmse,p99_err,max_err,"
    "bad_pixel_pct,flicker,light_scale,width,height,frame_over_hard,truth,truth_samples,"
    "pixels,nan_pixels,out_of_range_pixels,gl_errors,status";

std::string csvRow(const Row& r) {
    const auto& e = r.error;
    const double nan = std::nan("");
    std::vector<std::string> f{
        r.scene, r.method, r.params, number(r.gpuMs), number(r.cpuMs), number(r.frameMs),
        number(r.haveError ? e.meanAbs : nan), number(r.haveError ? e.rmse : nan),
        number(r.haveError ? e.p99 : nan), number(r.haveError ? e.max : nan),
        number(r.haveError ? e.badPixelPct : nan), number(r.flicker), number(r.lightScale),
        std::to_string(r.width), std::to_string(r.height), number(r.frameOverHard), r.truth,
        std::to_string(r.truthSamples), r.haveError ? std::to_string(e.pixels) : "",
        std::to_string(r.nanPixels), std::to_string(r.outOfRange), std::to_string(r.glErrors),
        r.status};
    std::string line;
    for (std::size_t i = 0; i < f.size(); ++i) line += (i ? "," : "") + csvField(f[i]);
    return line;
}

nlohmann::json rowJson(const Row& r) {
    auto num = [](double x) -> nlohmann::json {
        if (!std::isfinite(x)) return nullptr;
        return x;
    };
    nlohmann::json j = {{"scene", r.scene},
                        {"method", r.method},
                        {"params", r.params},
                        {"gpu_ms", num(r.gpuMs)},
                        {"cpu_ms", num(r.cpuMs)},
                        {"frame_ms", num(r.frameMs)},
                        {"flicker", num(r.flicker)},
                        {"light_scale", r.lightScale},
                        {"width", r.width},
                        {"height", r.height},
                        {"frame_over_hard", num(r.frameOverHard)},
                        {"truth", r.truth},
                        {"truth_samples", r.truthSamples},
                        {"nan_pixels", r.nanPixels},
                        {"out_of_range_pixels", r.outOfRange},
                        {"gl_errors", r.glErrors},
                        {"status", r.status}};
    const double nan = std::nan("");
    j["mean_abs_err"] = num(r.haveError ? r.error.meanAbs : nan);
    j["rmse"] = num(r.haveError ? r.error.rmse : nan);
    j["p99_err"] = num(r.haveError ? r.error.p99 : nan);
    j["max_err"] = num(r.haveError ? r.error.max : nan);
    j["bad_pixel_pct"] = num(r.haveError ? r.error.badPixelPct : nan);
    j["pixels"] = r.haveError ? nlohmann::json(r.error.pixels) : nlohmann::json(nullptr);
    return j;
}

std::string paramsText(const RunSpec& run) {
    std::string text;
    for (const gpu::ParameterValue& p : gpu::resolveParameters(*run.method, run.given))
        text += (text.empty() ? "" : ";") + p.name + "=" + p.value;
    if (run.method->usesSamples)
        text += (text.empty() ? "" : ";") + std::string("samples=") + std::to_string(run.samples);
    return text;
}

// A file-system-safe name for images of a run.
std::string slug(const std::string& s) {
    std::string out;
    for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' ? c : '_';
    return out;
}

// Light path for flicker: K + 1 positions, the centre moved along u from -sweep to +sweep light
// half-widths; position K/2 is the light itself (K is even).
std::vector<geometry::RectLight> lightPath(const geometry::RectLight& light, int steps,
                                           float sweep) {
    std::vector<geometry::RectLight> path;
    for (int i = 0; i <= steps; ++i) {
        geometry::RectLight l = light;
        const float t = steps ? -1.0f + 2.0f * static_cast<float>(i) / static_cast<float>(steps) : 0.0f;
        l.center += t * sweep * light.u;
        path.push_back(l);
    }
    return path;
}

class Bench {
public:
    Bench(const Options& opt, std::vector<fs::path> scenes, std::vector<RunSpec> runs, int width,
          int height, std::vector<double> scales)
        : mOpt(opt), mScenes(std::move(scenes)), mRuns(std::move(runs)), mWidth(width),
          mHeight(height), mScales(std::move(scales)), mOut(opt.outDir) {}

    int execute();
    std::size_t viewCount = 0; // views over all scenes (--cameras), for the progress count

private:
    const Options& mOpt;
    std::vector<fs::path> mScenes;
    std::vector<RunSpec> mRuns;
    int mWidth, mHeight;
    std::vector<double> mScales;
    fs::path mOut;
    std::ofstream mCsv;
    std::vector<Row> mRows;
    gpu::ContextInfo mInfo;
    std::size_t mRunIndex = 0, mRunTotal = 0;

    void writeRow(const Row& row) {
        mCsv << csvRow(row) << "\n";
        mCsv.flush();
        mRows.push_back(row);
    }
    // A row for every run, `base` with `status`: none of them could be rendered or scored.
    void writeRowForEveryRun(const Row& base, const std::string& status) {
        for (const RunSpec& run : mRuns) {
            Row row = base;
            row.method = std::string(run.method->name);
            row.params = paramsText(run);
            row.status = status;
            writeRow(row);
            ++mRunIndex;
        }
    }
    void writeJson(bool complete) const;
    int drawChart() const;

    gpu::RenderSettings settingsFor(const RunSpec& run, const geometry::RectLight& light) const {
        gpu::RenderSettings s;
        s.method = std::string(run.method->name);
        s.parameters = run.given;
        s.width = mWidth;
        s.height = mHeight;
        s.samples = run.samples;
        s.seed = mOpt.seed;
        s.light = light;
        s.camera = mCamera;
        s.progress = [](int, int) { checkInterrupt(); };
        return s;
    }

    void benchScene(const fs::path& path);
    void benchView(const geometry::Scene& scene, gpu::Renderer& renderer,
                   const std::string& sceneName, const geometry::RectLight& viewLight,
                   bool alphaTested);
    std::optional<geometry::Camera> mCamera; // the view's (benchScene)
};

void Bench::writeJson(bool complete) const {
    nlohmann::json j;
    j["gl_renderer"] = mInfo.renderer;
    j["gl_version"] = mInfo.version;
    j["cpu"] = apps::cpuModel();
    j["hardware_threads"] = std::thread::hardware_concurrency();
#ifdef PENUMBRA_BUILD_TYPE
    j["build_type"] = PENUMBRA_BUILD_TYPE;
#endif
    const std::time_t now = std::time(nullptr);
    char date[64];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    j["date"] = date;
    j["complete"] = complete;
    j["settings"] = {{"size", {mWidth, mHeight}},
                     {"truth", mOpt.truth},
                     {"truth_samples", mOpt.truthSamples},
                     {"frames", mOpt.frames},
                     {"warmup", mOpt.warmup},
                     {"flicker_steps", mOpt.flickerSteps},
                     {"sweep_half_widths", mOpt.sweep},
                     {"seed", mOpt.seed},
                     {"light_scales", mScales}};
    j["timing_note"] = "frame_ms: wall clock per frame including GPU completion; gpu_ms: GL "
                       "timestamp span of the frame; cpu_ms: CPU stages; medians over frames. "
                       "On llvmpipe the GPU is the CPU: compare as ratios (frame_over_hard).";
    nlohmann::json rows = nlohmann::json::array();
    for (const Row& r : mRows) rows.push_back(rowJson(r));
    j["runs"] = std::move(rows);
    apps::writeJsonFile(mOut / "results.json", j);
}

int Bench::drawChart() const {
    const fs::path script = fs::path(PENUMBRA_SOURCE_DIR) / "apps" / "bench" / "chart.py";
    const std::string cmd = "/usr/bin/python3 '" + script.string() + "' '" +
                            (mOut / "results.csv").string() + "' '" +
                            (mOut / "chart.png").string() + "' '" + mInfo.renderer + "'";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The views of a scene the bench measures (--cameras): a scene JSON's camera, or for a
// .gltf/.glb the glTF cameras asked for, each lit by the viewer's lamp for it (as
// penumbra-render and the viewer light them: geometry::lightAtView), or its framing.
struct BenchView {
    std::string name; // the scene column: the path, with "@cameraN" for a glTF camera
    geometry::Camera camera;
    geometry::RectLight light;
    std::string source; // camera and light, for the log
};

// The glTF cameras --cameras names for a scene ("framed", or a scene without cameras: none, one
// framed view). Throws InputError for an index the file does not have.
std::vector<int> cameraIndices(const fs::path& path, const geometry::Scene& scene,
                               const std::string& cameras) {
    std::vector<int> indices;
    if (scene.cameras.empty() || cameras == "framed") return indices;
    if (cameras == "all") {
        for (std::size_t i = 0; i < scene.cameras.size(); ++i) indices.push_back(int(i));
        return indices;
    }
    for (const std::string& item : splitList(cameras)) {
        char* end = nullptr;
        const long i = std::strtol(item.c_str(), &end, 10);
        if (end == item.c_str() || *end || i < 0 || i >= long(scene.cameras.size()))
            throw geometry::InputError(
                "--cameras: '" + item + "' is not a glTF camera of " + path.string() + " (" +
                std::to_string(scene.cameras.size()) + " cameras: 0 to " +
                std::to_string(scene.cameras.size() - 1) + ")");
        indices.push_back(int(i));
    }
    return indices;
}

std::vector<BenchView> benchViews(const fs::path& path, const geometry::Scene& loaded,
                                  const std::string& cameras) {
    std::vector<BenchView> views;
    const std::vector<int> indices = cameraIndices(path, loaded, cameras);
    if (indices.empty()) {
        geometry::Scene scene = loaded;
        if (!scene.cameras.empty()) geometry::selectFramedCamera(scene);
        views.push_back({path.string(), scene.camera, scene.light, scene.cameraSource});
        return views;
    }
    const geometry::RayTracer tracer(loaded); // one for every view's lamp
    for (const int i : indices) {
        geometry::Scene scene = loaded;
        geometry::selectCamera(scene, i);
        const std::string light = geometry::lightAtView(scene, false, &tracer);
        views.push_back({path.string() + "@camera" + std::to_string(i), scene.camera, scene.light,
                         scene.cameraSource + ", " + light});
    }
    return views;
}

void Bench::benchScene(const fs::path& path) {
    const auto t0 = std::chrono::steady_clock::now();
    // Levels are measured where players stand (DESIGN.md §5): from their glTF (spawn) cameras,
    // each with the viewer's lamp; --cameras framed keeps the automatic framed view.
    const geometry::Scene scene = geometry::loadScene(path);
    const std::vector<BenchView> views = benchViews(path, scene, mOpt.cameras);
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    std::fprintf(stderr, "scene %s: %zu triangles, %zu view%s, loaded in %.1f s\n",
                 path.string().c_str(), renderer.triangleCount(), views.size(),
                 views.size() == 1 ? "" : "s",
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    // The truth must see what the scene holds: `reference` occludes with whole triangles.
    const bool alphaTested = geometry::hasAlphaTestedCasters(scene);
    for (const BenchView& view : views) {
        std::fprintf(stderr, "view %s: %s\n", view.name.c_str(), view.source.c_str());
        mCamera = view.camera;
        benchView(scene, renderer, view.name, view.light, alphaTested);
    }
    mCamera.reset();
}

void Bench::benchView(const geometry::Scene& scene, gpu::Renderer& renderer,
                      const std::string& sceneName, const geometry::RectLight& viewLight,
                      bool alphaTested) {
    for (const double scale : mScales) {
        geometry::RectLight light = viewLight;
        light.u *= static_cast<float>(scale);
        light.v *= static_cast<float>(scale);
        Row base;
        base.scene = sceneName;
        base.lightScale = scale;
        base.width = mWidth;
        base.height = mHeight;
        base.truth = mOpt.truth;
        base.truthSamples = mOpt.truthSamples;
        // A scaled light that touches geometry: every run of this scale says so.
        try {
            geometry::validateLight(scene, light, "light scaled by " + number(scale));
        } catch (const geometry::InputError& e) {
            std::fprintf(stderr, "  light x%g: %s; skipped\n", scale, e.what());
            writeRowForEveryRun(base, std::string("refused: ") + e.what());
            continue;
        }

        // The truth of the static view and, for flicker, of every light position of the path.
        const RunSpec truthRun{&gpu::findMethod(mOpt.truth), {}, mOpt.truthSamples};
        if (alphaTested && !truthRun.method->alphaMasks) {
            const std::string why = "no truth (" + mOpt.truth +
                                    "): it occludes with whole triangles and the scene has "
                                    "alpha-tested casters; measure against --truth raytrace";
            std::fprintf(stderr, "  light x%g: %s\n", scale, why.c_str());
            writeRowForEveryRun(base, why);
            continue;
        }
        const int steps = mOpt.flickerSteps;
        std::vector<geometry::RectLight> path =
            steps > 0 ? lightPath(light, steps, mOpt.sweep) : std::vector<geometry::RectLight>{light};
        std::string pathProblem;
        for (std::size_t i = 0; i < path.size() && steps > 0; ++i)
            try {
                geometry::validateLight(scene, path[i], "light path position " + std::to_string(i));
            } catch (const geometry::InputError& e) {
                pathProblem = e.what();
                path = {light};
                std::fprintf(stderr, "  light x%g: flicker not measured: %s\n", scale, e.what());
                break;
            }
        const std::size_t middle = path.size() / 2;
        std::vector<geometry::FloatImage> truth;
        const auto tt = std::chrono::steady_clock::now();
        try {
            for (std::size_t i = 0; i < path.size(); ++i) {
                std::fprintf(stderr, "  light x%g: truth %s N=%d, position %zu/%zu\n", scale,
                             mOpt.truth.c_str(), mOpt.truthSamples, i + 1, path.size());
                renderer.renderFrame(settingsFor(truthRun, path[i]));
                truth.push_back(renderer.visibility());
            }
        } catch (const geometry::InputError& e) {
            // No truth (alpha-tested casters under `reference`): no run can be scored.
            std::fprintf(stderr, "  light x%g: no truth: %s\n", scale, e.what());
            writeRowForEveryRun(base, "no truth (" + mOpt.truth + "): " + e.what());
            continue;
        }
        std::fprintf(stderr, "  light x%g: truth done in %.1f s\n", scale,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - tt).count());
        const geometry::FloatImage& truthStatic = truth[middle];
        const fs::path imageDir = mOut / "images" / slug(sceneName);
        if (mOpt.saveImages) {
            fs::create_directories(imageDir);
            geometry::writePfm(imageDir / ("truth-x" + number(scale) + ".pfm"), truthStatic);
        }

        double hardFrame = NAN;
        for (std::size_t r = 0; r < mRuns.size(); ++r) {
            checkInterrupt();
            const RunSpec& run = mRuns[r];
            Row row = base;
            row.method = std::string(run.method->name);
            row.params = paramsText(run);
            ++mRunIndex;
            gpu::takeDebugErrors();
            try {
                const gpu::RenderSettings s = settingsFor(run, light);
                for (int f = 0; f < mOpt.warmup; ++f) renderer.renderFrame(s);
                std::vector<double> frame, gpuMs, cpuMs;
                for (int f = 0; f < mOpt.frames; ++f) {
                    checkInterrupt();
                    const gpu::FrameStats st = renderer.renderFrame(s);
                    frame.push_back(st.frameMs);
                    gpuMs.push_back(st.gpuFrameMs);
                    double cpu = 0.0;
                    for (const gpu::CpuTime& c : st.cpu) cpu += c.ms;
                    cpuMs.push_back(cpu);
                }
                row.frameMs = median(frame);
                row.gpuMs = median(gpuMs);
                row.cpuMs = median(cpuMs);
                const geometry::FloatImage v = renderer.visibility();
                row.error = geometry::compareVisibility(v.data, truthStatic.data);
                row.haveError = true;
                for (std::size_t i = 0; i < v.data.size(); ++i) {
                    const float x = v.data[i];
                    if (std::isfinite(truthStatic.data[i]) && !std::isfinite(x)) ++row.nanPixels;
                    if (std::isfinite(x) && (x < -1e-4f || x > 1.0f + 1e-4f)) ++row.outOfRange;
                }
                if (mOpt.saveImages) {
                    const std::string stem =
                        slug(row.method + (row.params.empty() ? "" : "_" + row.params)) + "-x" +
                        number(scale);
                    const geometry::RgbImage heat = geometry::errorHeatMap(
                        v.data, truthStatic.data, mWidth, mHeight);
                    geometry::writePng(imageDir / (stem + "-error.png"), heat.width, heat.height,
                                       3, heat.rgb.data());
                    const std::vector<std::uint8_t> rgba = renderer.imageRgba8();
                    geometry::writePng(imageDir / (stem + "-image.png"), mWidth, mHeight, 4,
                                       rgba.data());
                    geometry::writePfm(imageDir / (stem + "-visibility.pfm"), v);
                }
                if (path.size() > 1) {
                    std::vector<geometry::FloatImage> frames;
                    for (const geometry::RectLight& l : path) {
                        checkInterrupt();
                        renderer.renderFrame(settingsFor(run, l));
                        frames.push_back(renderer.visibility());
                    }
                    std::vector<std::span<const float>> a, b;
                    for (std::size_t i = 0; i < frames.size(); ++i) {
                        a.emplace_back(frames[i].data);
                        b.emplace_back(truth[i].data);
                    }
                    row.flicker = geometry::flicker(a, b);
                } else if (!pathProblem.empty()) {
                    row.status = "ok; flicker not measured: " + pathProblem;
                }
            } catch (const geometry::InputError& e) {
                row.status = std::string("refused: ") + e.what();
            } catch (const gpu::GlError& e) {
                row.status = std::string("GL error: ") + e.what();
                ++row.glErrors;
            }
            row.glErrors += gpu::takeDebugErrors().size();
            if (row.method == "hard" && run.given.empty()) hardFrame = row.frameMs;
            row.frameOverHard = row.frameMs / hardFrame;
            writeRow(row);
            if (row.haveError)
                std::fprintf(stderr,
                             "  [%zu/%zu] %-16s %-30s frame %8.2f ms (%sx hard)  err mean "
                             "%.4f p99 %.4f bad %5.2f%%  flicker %s%s\n",
                             mRunIndex, mRunTotal, row.method.c_str(), row.params.c_str(),
                             row.frameMs,
                             std::isfinite(row.frameOverHard) ? number(row.frameOverHard, 3).c_str()
                                                              : "-",
                             row.error.meanAbs, row.error.p99,
                             row.error.badPixelPct,
                             std::isfinite(row.flicker) ? number(row.flicker, 3).c_str() : "-",
                             row.glErrors ? "  GL ERRORS" : "");
            else
                std::fprintf(stderr, "  [%zu/%zu] %-16s %s\n", mRunIndex, mRunTotal,
                             row.method.c_str(), row.status.c_str());
        }
    }
}

int Bench::execute() {
    fs::create_directories(mOut);
    mCsv.open(mOut / "results.csv");
    if (!mCsv) throw std::runtime_error("cannot write " + (mOut / "results.csv").string());
    mCsv << kCsvHeader << "\n";
    mCsv.flush();

    gpu::EglContext context;
    mInfo = context.info();
    mRunTotal = (viewCount > 0 ? viewCount : mScenes.size()) * mScales.size() * mRuns.size();
    std::fprintf(stderr,
                 "penumbra-bench: %zu scenes x %zu runs x %zu light scales = %zu runs at %dx%d "
                 "on %s; truth %s N=%d; %d warm-up + %d timed frames; flicker %s\n",
                 mScenes.size(), mRuns.size(), mScales.size(), mRunTotal, mWidth, mHeight,
                 mInfo.renderer.c_str(), mOpt.truth.c_str(), mOpt.truthSamples, mOpt.warmup,
                 mOpt.frames,
                 mOpt.flickerSteps > 0
                     ? ("over " + std::to_string(mOpt.flickerSteps + 1) + " light positions").c_str()
                     : "off");
    bool interrupted = false;
    try {
        for (const fs::path& scene : mScenes) benchScene(scene);
    } catch (const Interrupted&) {
        interrupted = true;
        std::fprintf(stderr, "penumbra-bench: interrupted; %zu runs kept in %s\n", mRows.size(),
                     (mOut / "results.csv").string().c_str());
    }
    writeJson(!interrupted);
    if (interrupted) return kExitInterrupted;
    if (!mOpt.noChart) {
        const int rc = drawChart();
        if (rc != 0) {
            std::fprintf(stderr,
                         "penumbra-bench: error: the chart script failed (exit %d); results.csv "
                         "and results.json are written (Debian: apt install python3-matplotlib, "
                         "or --no-chart)\n",
                         rc);
            return apps::kExitInternalError;
        }
    }
    std::size_t failed = 0;
    for (const Row& r : mRows) failed += r.status.rfind("ok", 0) != 0 || r.glErrors || r.nanPixels;
    std::printf("penumbra-bench: %zu runs (%zu refused or failed) on %s; wrote %s/{results.csv, "
                "results.json%s}\n",
                mRows.size(), failed, mInfo.renderer.c_str(), mOut.string().c_str(),
                mOpt.noChart ? "" : ", chart.png");
    return 0;
}

int run(const Options& opt) {
    // Every input is checked before any work.
    const std::vector<std::string> methodNames = resolveMethods(opt.methods);
    const gpu::MethodInfo& truth = gpu::findMethod(opt.truth);
    if (!truth.usesSamples)
        throw geometry::InputError("--truth: '" + opt.truth + "' is not a reference method "
                                   "(reference or raytrace)");
    std::vector<std::string> withHard = methodNames;
    if (std::find(withHard.begin(), withHard.end(), "hard") == withHard.end())
        withHard.insert(withHard.begin(), "hard"); // the denominator of frame_over_hard
    else {
        withHard.erase(std::find(withHard.begin(), withHard.end(), "hard"));
        withHard.insert(withHard.begin(), "hard");
    }
    apps::checkSamples(opt.truthSamples, "--truth-samples");
    const std::vector<RunSpec> runs = expandRuns(withHard, opt.sweeps, opt.truthSamples);
    const auto [width, height] = apps::parseSize(opt.size, "256x256");
    if (opt.frames < 1 || opt.frames > 1000)
        throw geometry::InputError("--frames must be between 1 and 1000");
    if (opt.warmup < 0 || opt.warmup > 100)
        throw geometry::InputError("--warmup must be between 0 and 100");
    if (opt.flickerSteps < 0 || opt.flickerSteps > 256 || opt.flickerSteps % 2)
        throw geometry::InputError("--flicker-steps must be an even number between 0 and 256");
    if (!(opt.sweep > 0.0f && opt.sweep <= 100.0f))
        throw geometry::InputError("--sweep must be in (0, 100] light half-widths");
    std::vector<double> scales;
    for (const std::string& s : splitList(opt.lightScales)) {
        char* end = nullptr;
        const double x = std::strtod(s.c_str(), &end);
        if (end == s.c_str() || *end || !std::isfinite(x) || !(x > 0.0) || x > 1000.0)
            throw geometry::InputError("--light-scale: '" + s + "' is not a number in (0, 1000]");
        scales.push_back(x);
    }
    if (scales.empty()) throw geometry::InputError("--light-scale: no value");
    apps::checkOutputFolder("--out", opt.outDir);
    const std::vector<fs::path> scenes = expandScenes(opt.inputs);
    std::size_t views = 0;
    for (const fs::path& p : scenes) { // parse errors now, not an hour into the run
        std::fprintf(stderr, "checking %s\n", p.string().c_str());
        const geometry::Scene scene = geometry::loadScene(p);
        views += std::max<std::size_t>(1, cameraIndices(p, scene, opt.cameras).size());
    }
    if (!opt.noChart && access("/usr/bin/python3", X_OK) != 0)
        throw geometry::InputError("the chart needs /usr/bin/python3 with matplotlib (Debian: apt "
                                   "install python3-matplotlib), or give --no-chart");

    Bench bench(opt, scenes, runs, width, height, scales);
    bench.viewCount = views;
    return bench.execute();
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"penumbra-bench: scenes x methods x parameters, frame time against error"};
    Options opt;
    app.add_option("scenes", opt.inputs,
                   "scene JSON files, .gltf/.glb levels, or folders of them (a folder with any "
                   ".json gives its .json files only)")
        ->required();
    app.add_option("--methods", opt.methods,
                   "comma-separated method names, or 'all' (every implemented real-time "
                   "method: " + gpu::methodNameList(true) + "); hard always runs first")
        ->capture_default_str();
    app.add_option("--sweep", opt.sweeps,
                   "METHOD:NAME=V1,V2 — run the method once per value (repeatable; several "
                   "sweeps of one method multiply). NAME is a --param of the method, or "
                   "'samples' for reference/raytrace (their light samples; wedges-bitmask's samples is "
                   "its own parameter)");
    app.add_option("--light-scale", opt.lightScales,
                   "comma-separated factors on the light's size (u and v)")
        ->capture_default_str();
    apps::addSizeOption(app, opt.size);
    app.add_option("--truth", opt.truth, "what the error is measured against: reference (GPU) "
                                         "or raytrace (Embree; honours alpha masks)")
        ->capture_default_str();
    app.add_option("--truth-samples", opt.truthSamples, "light samples per pixel of the truth")
        ->capture_default_str();
    app.add_option("--frames", opt.frames, "timed frames per run (medians)")->capture_default_str();
    app.add_option("--warmup", opt.warmup, "untimed frames before them")->capture_default_str();
    app.add_option("--flicker-steps", opt.flickerSteps,
                   "steps of the light path for flicker (even; 0: not measured)")
        ->capture_default_str();
    app.add_option("--sweep-extent", opt.sweep,
                   "the light path: its centre moves along u by this many half-widths each way")
        ->capture_default_str();
    std::int64_t seed = opt.seed; // checked by apps::checkSeed
    app.add_option("--seed", seed, "sample pattern seed of the truth and reference runs")
        ->capture_default_str();
    app.add_option("--cameras", opt.cameras,
                   "views of a .gltf/.glb with glTF cameras: N,M,... (their indices), all, or "
                   "framed (the automatic framing with its light); each glTF camera is lit by the "
                   "viewer's lamp for its view, its rows named PATH@cameraN")
        ->capture_default_str();
    app.add_option("--out", opt.outDir, "output folder")->capture_default_str();
    app.add_flag("--save-images", opt.saveImages,
                 "also write per run image.png, visibility.pfm and error.png (heat map) under "
                 "OUT/images/");
    app.add_flag("--no-chart", opt.noChart, "do not draw chart.png");
    return apps::runCommandLine(app, argc, argv, "penumbra-bench",
                                apps::ParseErrorStyle::Prefixed, [&] {
        std::signal(SIGINT, onInterrupt);
        std::signal(SIGTERM, onInterrupt);
        try {
            opt.seed = apps::checkSeed(seed);
            return run(opt);
        } catch (const Interrupted&) { // not a std::exception
            std::fprintf(stderr, "penumbra-bench: interrupted before the first run\n");
            return kExitInterrupted;
        }
    });
}
