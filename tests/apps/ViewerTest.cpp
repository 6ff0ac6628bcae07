// penumbra-viewer end to end, in a real window under Xvfb (GLX on llvmpipe): it opens a level at
// its first glTF camera, renders frames with every registered method and writes a screenshot
// that shows lit and shadowed surfaces; without a display it exits 2 with a clear message.
// Xvfb is a dependency like any other: with CI set, a missing Xvfb fails these tests.
#include <geometry/scene/ImageIO.h>

#include <gpu/Methods.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>

namespace fs = std::filesystem;

namespace {

const std::string kViewer = std::string(PENUMBRA_BIN_DIR) + "/penumbra-viewer";
const std::string kLevel = std::string(PENUMBRA_SHARED_DIR) + "/levels/oa_dm4.glb";

struct RunResult {
    int exitCode = -1;
    std::string output;
};

RunResult runCommand(const std::string& command, const fs::path& log) {
    const int status = std::system((command + " > '" + log.string() + "' 2>&1").c_str());
    RunResult r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(log);
    std::stringstream ss;
    ss << in.rdbuf();
    r.output = ss.str();
    return r;
}

// One Xvfb server for the suite, on a display number it picks itself (-displayfd).
class Xvfb {
public:
    bool start(std::string& why) {
        int fds[2];
        if (pipe(fds) != 0) {
            why = "pipe failed";
            return false;
        }
        mPid = fork();
        if (mPid == 0) {
            close(fds[0]);
            const std::string fd = std::to_string(fds[1]);
            execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x1024x24",
                   "-nolisten", "tcp", static_cast<char*>(nullptr));
            _exit(127);
        }
        close(fds[1]);
        std::string number;
        pollfd p{fds[0], POLLIN, 0};
        char c = 0;
        while (poll(&p, 1, 20000) > 0 && read(fds[0], &c, 1) == 1 && c != '\n') number += c;
        close(fds[0]);
        if (number.empty()) {
            why = "Xvfb did not start (is the Debian package xvfb installed?)";
            stop();
            return false;
        }
        mDisplay = ":" + number;
        return true;
    }
    void stop() {
        if (mPid > 0) {
            kill(mPid, SIGTERM);
            waitpid(mPid, nullptr, 0);
            mPid = -1;
        }
    }
    const std::string& display() const { return mDisplay; }

private:
    pid_t mPid = -1;
    std::string mDisplay;
};

class Viewer : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        sServer = new Xvfb;
        if (!sServer->start(sWhy)) {
            delete sServer;
            sServer = nullptr;
        }
    }
    static void TearDownTestSuite() {
        if (sServer) sServer->stop();
        delete sServer;
        sServer = nullptr;
    }
    void SetUp() override {
        mDir = fs::temp_directory_path() / ("penumbra-viewer-" + std::to_string(std::random_device{}()));
        fs::create_directories(mDir);
    }
    // The viewer writes its F12/P screenshots into the working directory: run it in mDir.
    RunResult viewerIn(const std::string& args) {
        return runCommand("cd '" + mDir.string() + "' && DISPLAY=" + sServer->display() + " '" +
                              kViewer + "' " + args,
                          mDir / "log.txt");
    }
    void TearDown() override { fs::remove_all(mDir); }

    void requireDisplay() {
        if (sServer) return;
        if (std::getenv("CI")) FAIL() << sWhy;
        GTEST_SKIP() << sWhy;
    }
    RunResult viewer(const std::string& args) {
        return runCommand("DISPLAY=" + sServer->display() + " '" + kViewer + "' " + args,
                          mDir / "log.txt");
    }

    static Xvfb* sServer;
    static std::string sWhy;
    fs::path mDir;
};

Xvfb* Viewer::sServer = nullptr;
std::string Viewer::sWhy;

TEST_F(Viewer, EveryMethodRendersALevelFromItsSpawnCamera) {
    requireDisplay();
    if (HasFatalFailure() || IsSkipped()) return;
    for (const gpu::MethodInfo& m : gpu::methodTable()) {
        if (!m.implemented()) continue;
        const std::string name(m.name);
        SCOPED_TRACE(name);
        const fs::path shot = mDir / (name + ".png"), vis = mDir / (name + ".pfm"),
                       report = mDir / (name + ".json");
        // pdsm with 16 samples and 128² maps: its defaults build the level's deep map from
        // 256 shadow passes of 512², tens of seconds, minutes under the sanitizers.
        // deep-sm at 128², one ray per texel, for the same reason.
        const std::string params =
            name == "pdsm"      ? " --param samples=16 --param resolution=128"
            : name == "deep-sm" ? " --param resolution=128 --param supersample=1"
                                : "";
        const RunResult r = viewer("'" + kLevel + "' --method " + name + params +
                                   " --size 160x96 --frames 3 --samples 16 --hide-ui"
                                   " --screenshot '" + shot.string() + "' --visibility '" +
                                   vis.string() + "' --report '" + report.string() + "'");
        ASSERT_EQ(r.exitCode, 0) << r.output;
        // It opened at the first spawn point.
        EXPECT_NE(r.output.find("view 'spawn"), std::string::npos) << r.output;
        const geometry::Rgba8Image img = geometry::readPng(shot);
        ASSERT_EQ(img.width, 160);
        ASSERT_EQ(img.height, 96);
        const geometry::FloatImage v = geometry::readPfm(vis);
        ASSERT_EQ(v.width, 160);
        // Lit and shadowed surfaces, and the screenshot shows them: shadowed pixels are darker.
        double litLum = 0.0, darkLum = 0.0;
        int lit = 0, dark = 0, bad = 0;
        for (int i = 0; i < 160 * 96; ++i) {
            const float x = v.data[static_cast<std::size_t>(i)];
            if (std::isnan(x)) continue;
            if (!(x >= 0.0f && x <= 1.0f)) ++bad;
            const double lum = img.rgba[4 * i] + img.rgba[4 * i + 1] + img.rgba[4 * i + 2];
            if (x > 0.95f) {
                ++lit;
                litLum += lum;
            } else if (x < 0.05f) {
                ++dark;
                darkLum += lum;
            }
        }
        EXPECT_EQ(bad, 0) << "V outside [0, 1]";
        EXPECT_GT(lit, 160 * 96 / 50) << "fewer than 2% lit pixels";
        EXPECT_GT(dark, 160 * 96 / 50) << "fewer than 2% shadowed pixels";
        // Shadowed pixels show ambient light only; lit ones add n.l (grazing on this view's floor,
        // so the margin is modest): lit pixels are brighter on average and nearly all brighter
        // than the shadowed mean.
        if (lit > 0 && dark > 0) {
            const double darkMean = darkLum / dark;
            EXPECT_GT(litLum / lit, 1.2 * darkMean) << "shadows do not show in the screenshot";
            int brighter = 0;
            for (int i = 0; i < 160 * 96; ++i) {
                const float x = v.data[static_cast<std::size_t>(i)];
                if (!std::isnan(x) && x > 0.95f)
                    brighter += img.rgba[4 * i] + img.rgba[4 * i + 1] + img.rgba[4 * i + 2] > darkMean;
            }
            EXPECT_GT(brighter, lit * 9 / 10) << "lit pixels as dark as shadowed ones";
        }
        std::ifstream in(report);
        const nlohmann::json j = nlohmann::json::parse(in);
        EXPECT_EQ(j["method"], name);
        EXPECT_EQ(j["frames"], 3);
        EXPECT_GT(j["frame_ms_median"].get<double>(), 0.0);
    }
}

TEST_F(Viewer, FlyThroughAndLightAnimationRun) {
    requireDisplay();
    if (HasFatalFailure() || IsSkipped()) return;
    const fs::path shot = mDir / "tour.png";
    const RunResult r = viewer("'" + kLevel + "' --method wedges-blend --size 128x80 --frames 12"
                               " --fly-through --leg-frames 4 --animate-light --screenshot '" +
                               shot.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(shot));
    // Rendering at half the window's size: V has half the pixels each way, the screenshot all.
    const fs::path half = mDir / "half.png", vis = mDir / "half.pfm";
    const RunResult h = viewer("'" + kLevel + "' --method hard --size 128x80 --render-scale 0.5 "
                               "--frames 2 --hide-ui --screenshot '" + half.string() +
                               "' --visibility '" + vis.string() + "'");
    ASSERT_EQ(h.exitCode, 0) << h.output;
    const geometry::FloatImage v = geometry::readPfm(vis);
    EXPECT_EQ(v.width, 64);
    EXPECT_EQ(v.height, 40);
    const geometry::Rgba8Image img = geometry::readPng(half);
    EXPECT_EQ(img.width, 128);
    EXPECT_EQ(img.height, 80);
}

// --simplify as penumbra-render's (apps/Flags.h), made under the light the scene is loaded
// with: the report and the first lines say what it replaced, and the frame draws the stand-in.
TEST_F(Viewer, SimplifiedStandInsAreDrawnAndReported) {
    requireDisplay();
    if (HasFatalFailure() || IsSkipped()) return;
    std::ifstream in(std::string(PENUMBRA_SOURCE_DIR) + "/data/sphere.json");
    std::stringstream text;
    text << in.rdbuf();
    std::string json = text.str();
    const auto at = json.find("\"segments\": 48");
    ASSERT_NE(at, std::string::npos) << json;
    json.replace(at, std::string("\"segments\": 48").size(), "\"segments\": 256");
    const fs::path scene = mDir / "fine-sphere.json", report = mDir / "report.json";
    std::ofstream(scene) << json;
    const RunResult r = viewer("--scene '" + scene.string() + "' --method auto --size 128x80 " +
                               "--frames 2 --simplify 0.1 --report '" + report.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("simplify: visibility error about 0.1: 2 meshes"), std::string::npos)
        << r.output;
    nlohmann::json j;
    std::ifstream(report) >> j;
    const std::size_t before = j["simplify"]["triangles_before"];
    const std::size_t after = j["simplify"]["triangles_after"];
    EXPECT_EQ(before, 2u + 2u * 256u * 127u); // the floor and the 256-segment sphere
    EXPECT_LT(after, before / 4);
    EXPECT_EQ(j["triangles"], after);
}

TEST_F(Viewer, ScriptedKeysDriveTheApp) {
    requireDisplay();
    if (HasFatalFailure() || IsSkipped()) return;
    const fs::path shot = mDir / "keys.png";
    const std::string scene = std::string(PENUMBRA_SOURCE_DIR) + "/data/plates-three.json";
    // C next view, O orbit, L light animation, W forward, P screenshot, F1/Tab hide the UI,
    // R reload shaders, then a scene dropped on the window.
    const RunResult r = viewerIn("'" + kLevel + "' --method hard --size 128x80 --frames 12 --keys "
                               "2:C,3:O,4:L,5:W,6:P,7:F1,8:Tab,9:R,10:drop='" + scene +
                               "' --screenshot '" + shot.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("frame 6: wrote penumbra-"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("frame 9: shaders reloaded"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("frame 10: loaded " + scene), std::string::npos) << r.output;
    int timestamped = 0;
    for (const auto& e : fs::directory_iterator(mDir))
        timestamped += e.path().filename().string().rfind("penumbra-", 0) == 0;
    EXPECT_EQ(timestamped, 1) << "P writes one timestamped PNG into the working directory";
    // Esc ends a scripted run early and says so.
    const RunResult esc = viewer("'" + kLevel + "' --method hard --size 64x64 --frames 50 --keys 3:Esc");
    EXPECT_EQ(esc.exitCode, 0) << esc.output;
    EXPECT_NE(esc.output.find("quit (Esc) at frame 4 of 50"), std::string::npos) << esc.output;
    const fs::path never = mDir / "never.png";
    const RunResult escShot = viewer("'" + kLevel + "' --method hard --size 64x64 --frames 50 "
                                     "--keys 3:Esc --screenshot '" + never.string() + "'");
    EXPECT_EQ(escShot.exitCode, 0) << escShot.output;
    EXPECT_NE(escShot.output.find("no screenshot written"), std::string::npos) << escShot.output;
    EXPECT_EQ(escShot.output.find("wrote " + never.string()), std::string::npos) << escShot.output;
    EXPECT_FALSE(fs::exists(never));
    // A bad drop is reported and the level stays.
    const RunResult bad = viewer("'" + kLevel + "' --method hard --size 64x64 --frames 4 --keys "
                                 "1:drop=/no/such.glb");
    EXPECT_EQ(bad.exitCode, 0) << bad.output;
    EXPECT_NE(bad.output.find("could not load /no/such.glb"), std::string::npos) << bad.output;
}

TEST_F(Viewer, AFailedShaderReloadKeepsThePreviousPrograms) {
    requireDisplay();
    if (HasFatalFailure() || IsSkipped()) return;
    const fs::path shaders = mDir / "shaders";
    fs::copy(std::string(PENUMBRA_SOURCE_DIR) + "/shaders", shaders, fs::copy_options::recursive);
    const fs::path shot = mDir / "reload.png", go = mDir / "go";
    // The viewer starts on good shaders and waits at frame 3 for `go`; meanwhile the G-buffer
    // shader is broken; then R: the reload must fail, and the frames after it still render.
    const std::string cmd = "DISPLAY=" + sServer->display() + " PENUMBRA_SHADER_DIR='" +
                            shaders.string() + "' timeout 170 '" + kViewer + "' '" + kLevel +
                            "' --method hard --size 64x64 --hide-ui --frames 8 --keys 3:wait='" +
                            go.string() + "',4:R --screenshot '" + shot.string() + "'";
    RunResult r;
    std::thread viewer([&] { r = runCommand(cmd, mDir / "reload.txt"); });
    auto log = [&] {
        std::ifstream in(mDir / "reload.txt");
        return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    };
    for (int i = 0; i < 3000 && log().find("frame 3: waiting for") == std::string::npos; ++i)
        usleep(50000); // up to 150 s; the viewer's own timeout ends it before
    std::ofstream(shaders / "gbuffer.frag", std::ios::app) << "\nthis is not GLSL;\n";
    std::ofstream(go) << "go\n";
    viewer.join();
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("frame 4: shader reload failed, keeping the previous programs"),
              std::string::npos) << r.output;
    EXPECT_NE(r.output.find("gbuffer.frag:"), std::string::npos) << "names file:line: " << r.output;
    const geometry::Rgba8Image img = geometry::readPng(shot);
    int nonBackground = 0;
    for (std::size_t i = 0; i < img.rgba.size(); i += 4) nonBackground += img.rgba[i] > 20;
    EXPECT_GT(nonBackground, 64 * 64 / 2) << "frames after the failed reload still render";
}

// At a glTF camera the viewer hangs a lamp under the ceiling ahead (the level's framed light
// rarely reaches a spawn room): more of the view is lit than under --scene-light.
TEST_F(Viewer, ALampIsHungAtEachSpawnView) {
    requireDisplay();
    if (HasFatalFailure() || IsSkipped()) return;
    auto litShare = [&](const std::string& extra, std::string& output) {
        const fs::path vis = mDir / "lamp.pfm";
        const RunResult r = viewer("'" + kLevel + "' --method hard --size 96x64 --frames 2 " +
                                   extra + " --visibility '" + vis.string() + "'");
        EXPECT_EQ(r.exitCode, 0) << r.output;
        output = r.output;
        const geometry::FloatImage v = geometry::readPfm(vis);
        int lit = 0, surface = 0;
        for (float x : v.data)
            if (!std::isnan(x)) {
                ++surface;
                lit += x > 0.5f;
            }
        return surface > 0 ? double(lit) / surface : 0.0;
    };
    std::string withLamp, withScene, hung;
    const double lamp = litShare("", withLamp);
    const double scene = litShare("--scene-light", withScene);
    EXPECT_NE(withLamp.find("frame 0: lamp hung at"), std::string::npos) << withLamp;
    EXPECT_EQ(withScene.find("lamp hung"), std::string::npos) << withScene;
    EXPECT_GT(lamp, scene + 0.2) << "lamp " << lamp << " vs scene light " << scene;
    // H hangs one wherever the camera is, also under --scene-light.
    litShare("--scene-light --keys 1:C,1:H", hung);
    EXPECT_NE(hung.find("frame 1: lamp hung at"), std::string::npos) << hung;
}

// One view everywhere: penumbra-render at a glTF camera lights it with the viewer's lamp, so the
// two programs give the same V there (the textured level: the alpha-tested part goes to
// occlusion in both); --scene-light in both keeps the file's light, and again they agree.
TEST_F(Viewer, RenderAndViewerGiveTheSameVisibilityAtASpawnCamera) {
    requireDisplay();
    if (HasFatalFailure() || IsSkipped()) return;
    const std::string render = std::string(PENUMBRA_BIN_DIR) + "/penumbra-render";
    const std::string level = std::string(PENUMBRA_SHARED_DIR) + "/levels/textured/oa_dm4.glb";
    for (const std::string light : {"", " --scene-light"}) {
        const fs::path vis = mDir / "viewer.pfm", out = mDir / "render";
        const RunResult v = viewer("'" + level + "' --camera 1 --method auto --size 96x64 " +
                                   "--frames 2 --visibility '" + vis.string() + "'" + light);
        ASSERT_EQ(v.exitCode, 0) << v.output;
        const RunResult r = runCommand("'" + render + "' --scene '" + level +
                                           "' --camera 1 --method auto --size 96x64 --out '" +
                                           out.string() + "'" + light,
                                       mDir / "render-log.txt");
        ASSERT_EQ(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find(light.empty() ? "light: lamp at the view" : "--scene-light"),
                  std::string::npos)
            << r.output;
        const geometry::FloatImage a = geometry::readPfm(vis);
        const geometry::FloatImage b = geometry::readPfm(out / "visibility.pfm");
        ASSERT_EQ(a.data.size(), b.data.size());
        double sum = 0.0;
        std::size_t surface = 0, coverage = 0;
        for (std::size_t i = 0; i < a.data.size(); ++i) {
            coverage += std::isfinite(a.data[i]) != std::isfinite(b.data[i]);
            if (!std::isfinite(a.data[i]) || !std::isfinite(b.data[i])) continue;
            sum += std::abs(a.data[i] - b.data[i]);
            ++surface;
        }
        EXPECT_EQ(coverage, 0u) << light;
        ASSERT_GT(surface, 1000u) << light;
        EXPECT_LE(sum / double(surface), 0.001) << light; // measured: 0
    }
}

TEST(ViewerNoDisplay, ExitsTwoWithAClearMessage) {
    const fs::path log = fs::temp_directory_path() / "penumbra-viewer-nodisplay.txt";
    const RunResult r = runCommand("env -u DISPLAY -u WAYLAND_DISPLAY '" + kViewer + "' '" + kLevel +
                                       "' --frames 1",
                                   log);
    fs::remove(log);
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("no display"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("Xvfb"), std::string::npos) << "says how to run it headless";
}

TEST(ViewerNoDisplay, BadInputIsRefusedBeforeAWindowOpens) {
    const fs::path log = fs::temp_directory_path() / "penumbra-viewer-badinput.txt";
    struct Case {
        std::string args, needle;
    } cases[] = {
        {"'" + kLevel + "' --method nope", "nope"},
        {"'" + kLevel + "' --size 10x10", "--size"},
        // The window's own bounds, inside the limits every app shares (apps/Flags.h).
        {"'" + kLevel + "' --size 10x10", "of the viewer's window must be between 64 and 8192"},
        {"'" + kLevel + "' --size 9000x600", "of the viewer's window must be between 64 and 8192"},
        {"'" + kLevel + "' --size 16385x600", "--size: each side must be between 1 and 16384"},
        {"'" + kLevel + "' --samples 65537", "--samples must be between 1 and 65536"},
        {"'" + kLevel + "' --samples 0", "--samples must be between 1 and 65536"},
        {"'" + kLevel + "' --render-scale 2", "--render-scale"},
        {"'" + kLevel + "' --simplify 0.5", "--simplify must be between 0 (off) and 0.25"},
        {"'" + kLevel + "' --keys 3:X --frames 5", "unknown key 'X'"},
        {"'" + kLevel + "' --debug-view nope", "nope"},
        {"'" + kLevel + "' --camera 99", "--camera 99"},
        {"/no/such/file.glb", "not found"},
        {"", "give one scene"},
        {"'" + kLevel + "' --screenshot /tmp/x.png", "--frames"},
        {"'" + kLevel + "' --frames 1 --screenshot /no/such/dir/x.png", "does not exist"},
    };
    for (const Case& c : cases) {
        const RunResult r = runCommand("env -u DISPLAY -u WAYLAND_DISPLAY '" + kViewer + "' " + c.args, log);
        EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
    }
    fs::remove(log);
}

} // namespace
