// penumbra-soak: many frames on a level with the camera flying through its spawn points and the
// light moving, every registered method in turn, checking what a long run must keep:
// - no GL error and no exception in any frame;
// - V finite and in [0, 1] wherever there is a surface (NaN only where there is none);
// - memory that does not grow: the process's resident size (on llvmpipe the "GPU" memory is the
//   process's own) and, where the driver reports it (GL_NVX_gpu_memory_info), the GPU's free
//   memory. The run is one sequence of frames (method, camera, light, seed) played three times.
//   The first is the warm-up: every method creates its state and reaches its high-water marks
//   (caches, buffers sized to the busiest view). The second and third play the same frames on
//   the same state, so the third's peak may exceed the second's by at most --growth-limit MiB;
//   a leak of L per frame shows as about L x frames / 3. (Comparing the warm-up against the
//   second playing is not enough: a method's transient peak in the warm-up sits on the memory
//   of the methods created before it, in the second on that of all of them.)
// Exit 0 when every check holds, 1 when one fails (each failure is printed), 2 on bad input.
#include <apps/AppCommon.h>
#include <apps/Flags.h>
#include <apps/Report.h>

#include <geometry/core/Error.h>
#include <geometry/reference/RayTracer.h>
#include <geometry/scene/Scene.h>
#include <geometry/reference/Framing.h>
#include <gpu/gl/Context.h>
#include <gpu/Methods.h>
#include <gpu/Renderer.h>
#include <gpu/gl/ShaderLoader.h>

#include <ViewerCore.h>

#include <CLI/CLI.hpp>
#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;

constexpr int kExitFailed = 1;

struct Options {
    std::string scene = "../shared/levels/oa_dm4.glb";
    std::string size = "128x128";
    int frames = 3000;     // in all, over every method
    int methodFrames = 10; // frames of one method before the next takes over
    int legFrames = 60;    // frames from one glTF camera to the next
    int samples = 4;       // reference, raytrace
    int checkEvery = 1;    // read V back every N frames
    double growthLimitMiB = 8.0;
    std::vector<std::string> methods; // empty: every implemented one
    std::string report;
    int injectLeakKiB = 0; // testing the check itself: memory kept (and touched) per frame
};

double residentMiB() {
    std::ifstream statm("/proc/self/statm");
    long pages = 0, resident = 0;
    statm >> pages >> resident;
    return double(resident) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

// Free GPU memory in MiB where the driver reports it (NVIDIA), else a negative value.
double gpuFreeMiB() {
    if (!epoxy_has_gl_extension("GL_NVX_gpu_memory_info")) return -1.0;
    GLint kib = 0;
    glGetIntegerv(0x9049 /* GL_GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX */, &kib);
    return double(kib) / 1024.0;
}

struct MethodTally {
    int frames = 0, errors = 0, badV = 0, checked = 0, lightsRefused = 0;
    std::vector<double> ms;
};

int run(const Options& opt) {
    const auto [width, height] = apps::parseSize(opt.size, "128x128");
    if (opt.frames < 1 || opt.frames > 10000000)
        throw geometry::InputError("--frames must be between 1 and 10000000");
    if (opt.methodFrames < 1) throw geometry::InputError("--method-frames must be at least 1");
    if (opt.legFrames < 1) throw geometry::InputError("--leg-frames must be at least 1");
    apps::checkSamples(opt.samples);
    if (opt.checkEvery < 1) throw geometry::InputError("--check-every must be at least 1");
    if (!opt.report.empty() && fs::is_directory(opt.report))
        throw geometry::InputError("--report " + opt.report + ": is a directory");

    std::vector<std::string> methods = opt.methods;
    if (methods.empty()) {
        for (const gpu::MethodInfo& m : gpu::methodTable())
            if (m.create) methods.emplace_back(m.name);
    } else {
        for (const std::string& m : methods) gpu::findMethod(m); // InputError if unknown
    }

    geometry::Scene scene = geometry::loadScene(opt.scene);
    // The path: the glTF cameras (spawn points), else the framed view alone; at each, a lamp
    // hung under the ceiling ahead as the viewer does (else the scene's light).
    std::vector<geometry::Camera> cameras;
    for (const geometry::NamedCamera& c : scene.cameras) cameras.push_back(c.camera);
    if (cameras.empty()) cameras.push_back(scene.camera);
    std::vector<geometry::RectLight> lamps;
    {
        const geometry::RayTracer tracer(scene);
        for (const geometry::Camera& c : cameras)
            lamps.push_back(viewer::lampAhead(scene, tracer, c).value_or(scene.light));
    }

    gpu::EglContext context;
    const gpu::ContextInfo info = context.info();
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    const std::size_t methodCount = methods.size();
    // The sequence: a third of the frames, played three times (a warm-up and two compared).
    constexpr int kPlayings = 3;
    const int period = std::max(opt.frames / kPlayings, 1);
    std::printf("penumbra-soak: %s, %dx%d, %d frames (a sequence of %d played three times: a "
                "warm-up, then two compared), methods %d "
                "frames each in turn: ",
                opt.scene.c_str(), width, height, opt.frames, period, opt.methodFrames);
    for (std::size_t i = 0; i < methodCount; ++i)
        std::printf("%s%s", i ? ", " : "", methods[i].c_str());
    std::printf("\n  renderer: %s\n  CPU: %s\n", info.renderer.c_str(), apps::cpuModel().c_str());

    std::map<std::string, MethodTally> tally;
    std::vector<double> rss(static_cast<std::size_t>(opt.frames)),
        gpuFree(static_cast<std::size_t>(opt.frames));
    std::vector<std::string> failures;
    auto fail = [&](std::string message) {
        if (failures.size() < 20) std::printf("  FAIL %s\n", message.c_str());
        failures.push_back(std::move(message));
    };
    const double rssStart = residentMiB();
    const auto t0 = std::chrono::steady_clock::now();
    for (int frame = 0; frame < opt.frames; ++frame) {
        const std::string& method =
            methods[static_cast<std::size_t>(frame % period / opt.methodFrames) % methodCount];
        MethodTally& m = tally[method];
        const int leg = (frame % period / opt.legFrames) % int(cameras.size());
        const geometry::RectLight& lamp = lamps[static_cast<std::size_t>(leg)];
        const viewer::LightRig rig = viewer::LightRig::fromLight(lamp);
        gpu::RenderSettings s;
        s.method = method;
        s.width = width;
        s.height = height;
        s.samples = opt.samples;
        // pdsm builds its deep map again whenever the light moves, here every frame: at its
        // smallest (16 samples, 128² maps) as the truth methods take --samples, not its
        // defaults' 256 shadow passes of 512² and their merge (tens of seconds a frame).
        if (method == "pdsm") s.parameters = {{"samples", "16"}, {"resolution", "128"}};
        // deep-sm traces its deep maps again whenever the light moves: at 128², one ray per
        // texel, not its defaults' 3 x 3 rays per texel of up to six 512² faces (seconds a
        // frame on a level).
        if (method == "deep-sm") s.parameters = {{"resolution", "128"}, {"supersample", "1"}};
        const int k = frame % period; // the frame of the sequence
        s.seed = static_cast<std::uint32_t>(k + 1);
        s.camera = viewer::flyThrough(cameras, k, opt.legFrames);
        // A circle of half the lamp's size: it moves every frame and seldom reaches a wall.
        s.light = rig.animated(float(k) / 30.0f, 0.5f * std::max(rig.halfU, rig.halfV));
        const auto f0 = std::chrono::steady_clock::now();
        try {
            try {
                renderer.renderFrame(s);
            } catch (const geometry::LightRefusedError&) {
                // The moving lamp touched geometry (refused, as the viewer refuses it): the
                // frame is rendered with the lamp where it hangs.
                ++m.lightsRefused;
                s.light = lamp;
                renderer.renderFrame(s);
            }
            ++m.frames;
            m.ms.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - f0)
                    .count());
            if (frame % opt.checkEvery == 0) {
                ++m.checked;
                const geometry::FloatImage v = renderer.visibility();
                const geometry::FloatImage p = renderer.position();
                std::size_t bad = 0;
                for (std::size_t i = 0; i < v.data.size(); ++i) {
                    const bool surface = std::isfinite(p.data[3 * i]);
                    const float x = v.data[i];
                    bad += surface ? !(x >= 0.0f && x <= 1.0f) : !std::isnan(x);
                }
                if (bad > 0) {
                    ++m.badV;
                    fail("frame " + std::to_string(frame) + " " + method + ": " +
                         std::to_string(bad) + " pixels with V not finite in [0, 1]");
                }
            }
        } catch (const std::exception& e) {
            ++m.errors;
            fail("frame " + std::to_string(frame) + " " + method + ": " + e.what());
        }
        if (opt.injectLeakKiB > 0) {
            static std::vector<std::vector<char>> kept;
            kept.emplace_back(std::size_t(opt.injectLeakKiB) * 1024, char(frame));
        }
        rss[static_cast<std::size_t>(frame)] = residentMiB();
        gpuFree[static_cast<std::size_t>(frame)] = gpuFreeMiB();
        const int every = std::max(opt.frames / 10, 1);
        if ((frame + 1) % every == 0 || frame + 1 == opt.frames) {
            const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
                                 .count();
            std::printf("  frame %d/%d  %.0f s  resident %.1f MiB\n", frame + 1, opt.frames, s,
                        rss[static_cast<std::size_t>(frame)]);
            std::fflush(stdout);
        }
    }

    // Memory: the peak of the third playing against the second's. Both play the same frames on
    // the warmed-up state, so their transient peaks are the same; a leak raises the third's.
    auto peak = [](const std::vector<double>& v, int from, int to, double sign) {
        double p = -1e300;
        for (int i = from; i < to; ++i) p = std::max(p, sign * v[static_cast<std::size_t>(i)]);
        return sign * p;
    };
    const bool compared = opt.frames >= kPlayings * period && period >= 1;
    const double rssWarmUp = peak(rss, 0, period, 1.0);
    const double rssSecond = compared ? peak(rss, period, 2 * period, 1.0) : 0.0;
    const double rssThird = compared ? peak(rss, 2 * period, 3 * period, 1.0) : 0.0;
    const double rssGrowth = rssThird - rssSecond;
    if (compared && rssGrowth > opt.growthLimitMiB)
        fail("resident memory grew by " + std::to_string(rssGrowth) + " MiB (peak " +
             std::to_string(rssSecond) + " -> " + std::to_string(rssThird) +
             ") the third time through the same frames");
    double gpuDrop = 0.0;
    const bool gpuKnown = gpuFree.back() >= 0.0;
    if (gpuKnown && compared) {
        // Free memory falling is growth: the lowest free of each compared playing.
        gpuDrop = peak(gpuFree, period, 2 * period, -1.0) -
                  peak(gpuFree, 2 * period, 3 * period, -1.0);
        if (gpuDrop > opt.growthLimitMiB)
            fail("GPU free memory fell by " + std::to_string(gpuDrop) +
                 " MiB the third time through the same frames");
    }

    std::printf("\n| method | frames | median ms | GL errors / exceptions | frames with bad V "
                "(checked) | lights refused |\n|---|---:|---:|---:|---:|---:|\n");
    nlohmann::json report;
    for (const std::string& name : methods) {
        MethodTally& m = tally[name];
        const double median = apps::median(m.ms, 0.0);
        std::printf("| %s | %d | %.1f | %d | %d (%d) | %d |\n", name.c_str(), m.frames, median,
                    m.errors, m.badV, m.checked, m.lightsRefused);
        report["methods"][name] = {{"frames", m.frames},   {"median_ms", median},
                                   {"errors", m.errors},   {"bad_v_frames", m.badV},
                                   {"checked", m.checked}, {"lights_refused", m.lightsRefused}};
    }
    if (compared)
        std::printf("\nresident memory: %.1f MiB at start; peak %.1f in the warm-up, %.1f the "
                    "second time through the frames, %.1f the third: growth %.2f MiB (limit "
                    "%.1f)\n",
                    rssStart, rssWarmUp, rssSecond, rssThird, rssGrowth, opt.growthLimitMiB);
    else
        std::printf("\nresident memory: %.1f MiB at start; peak %.1f; growth not checked (fewer "
                    "than %d frames: the sequence is not played three times)\n",
                    rssStart, rssWarmUp, kPlayings);
    if (gpuKnown)
        std::printf("GPU free memory: fell by %.2f MiB the third time\n", gpuDrop);
    else
        std::printf("GPU memory: not reported by this driver (llvmpipe keeps it in the process: "
                    "the resident size above)\n");
    std::printf("%s: %zu failure(s)\n", failures.empty() ? "PASS" : "FAIL", failures.size());
    if (!opt.report.empty()) {
        report["scene"] = opt.scene;
        report["size"] = {width, height};
        report["frames"] = opt.frames;
        report["sequence_frames"] = period;
        report["resident_mib"] = {{"start", rssStart},
                                  {"warm_up_peak", rssWarmUp},
                                  {"second_peak", rssSecond},
                                  {"third_peak", rssThird},
                                  {"growth", rssGrowth}};
        if (gpuKnown) report["gpu_free_drop_mib"] = gpuDrop;
        report["gl_renderer"] = info.renderer;
        report["cpu"] = apps::cpuModel();
        report["failures"] = failures;
        apps::writeJsonFile(opt.report, report);
    }
    return failures.empty() ? 0 : kExitFailed;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"penumbra-soak: many frames on a level, every method, checking GL errors, V and "
                 "memory growth"};
    Options opt;
    app.add_option("--scene", opt.scene, "a .glb/.gltf level (its glTF cameras are the path) or "
                                         "scene JSON")
        ->capture_default_str();
    apps::addSizeOption(app, opt.size);
    app.add_option("--frames", opt.frames, "frames in all: a sequence of a third of them, played three "
                                 "times (a warm-up, then two compared for memory growth)")
        ->capture_default_str();
    app.add_option("--method-frames", opt.methodFrames,
                   "frames of one method before the next takes over")
        ->capture_default_str();
    app.add_option("--leg-frames", opt.legFrames, "frames from one glTF camera to the next")
        ->capture_default_str();
    apps::addSamplesOption(app, opt.samples);
    app.add_option("--check-every", opt.checkEvery, "read V back every N frames")
        ->capture_default_str();
    app.add_option("--growth-limit", opt.growthLimitMiB,
                   "MiB the memory may grow the third time through the frames over the second "
                   "(peak over peak)")
        ->capture_default_str();
    apps::addMethodOption(app, opt.methods, "a method to run (repeatable; default: every one)");
    app.add_option("--report", opt.report, "write the results as JSON");
    app.add_option("--inject-leak", opt.injectLeakKiB,
                   "testing the memory check: keep this many KiB more every frame")
        ->group("Testing");
    return apps::runCommandLine(app, argc, argv, "penumbra-soak", apps::ParseErrorStyle::Cli11,
                                [&] { return run(opt); });
}
