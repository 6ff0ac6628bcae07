#include "Viewer.h"

#include "ViewerCore.h"

#include <apps/AppCommon.h>
#include <apps/Flags.h>
#include <apps/Report.h>

#include <geometry/core/Error.h>
#include <geometry/reference/Framing.h>
#include <geometry/scene/ImageIO.h>
#include <geometry/reference/RayTracer.h>
#include <geometry/scene/Scene.h>
#include <gpu/gl/Context.h>
#include <gpu/Renderer.h>
#include <gpu/gl/State.h>

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <deque>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <regex>
#include <sstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace viewer {

namespace {

// A named view of the scene: its glTF cameras (spawn points) in file order, or the scene's own.
struct View {
    std::string name;
    geometry::Camera camera;
};

std::vector<View> sceneViews(const geometry::Scene& scene) {
    std::vector<View> views;
    for (const auto& c : scene.cameras) views.push_back({c.name, c.camera});
    if (views.empty())
        views.push_back({scene.cameraSource.empty() ? "scene camera" : scene.cameraSource,
                         scene.camera});
    return views;
}

std::string timestampedName() {
    const std::time_t t = std::time(nullptr);
    char buf[64];
    std::strftime(buf, sizeof buf, "penumbra-%Y%m%d-%H%M%S", std::localtime(&t));
    std::string name = buf;
    for (int i = 2; fs::exists(name + ".png"); ++i) name = std::string(buf) + "-" + std::to_string(i);
    return name + ".png";
}

struct ScriptedKey {
    int frame = 0;
    int key = GLFW_KEY_UNKNOWN; // or
    std::string drop;           // a dropped file, or
    std::string wait;           // a file to wait for (scripts synchronise with the viewer)
};

std::vector<ScriptedKey> parseKeys(const std::string& text) {
    static const std::pair<const char*, int> names[] = {
        {"F1", GLFW_KEY_F1}, {"F12", GLFW_KEY_F12}, {"P", GLFW_KEY_P},     {"R", GLFW_KEY_R},
        {"C", GLFW_KEY_C},   {"O", GLFW_KEY_O},     {"L", GLFW_KEY_L},     {"Tab", GLFW_KEY_TAB},
        {"Esc", GLFW_KEY_ESCAPE}, {"W", GLFW_KEY_W}, {"A", GLFW_KEY_A},    {"S", GLFW_KEY_S},
        {"D", GLFW_KEY_D},   {"Q", GLFW_KEY_Q},     {"E", GLFW_KEY_E},     {"V", GLFW_KEY_V},
        {"H", GLFW_KEY_H}};
    std::vector<ScriptedKey> keys;
    std::stringstream in(text);
    std::string item;
    static const std::regex re(R"((\d{1,7}):(.+))");
    while (std::getline(in, item, ',')) {
        std::smatch m;
        if (!std::regex_match(item, m, re))
            throw geometry::InputError("--keys: expected FRAME:KEY, got '" + item + "'");
        ScriptedKey k;
        k.frame = std::stoi(m[1]);
        const std::string key = m[2];
        if (key.rfind("drop=", 0) == 0) {
            k.drop = key.substr(5);
        } else if (key.rfind("wait=", 0) == 0) {
            k.wait = key.substr(5);
        } else {
            for (const auto& [name, code] : names)
                if (key == name) k.key = code;
            if (k.key == GLFW_KEY_UNKNOWN)
                throw geometry::InputError("--keys: unknown key '" + key +
                                           "' (F1 F12 P R C O L V H Tab Esc W A S D Q E, drop=PATH, "
                                           "wait=PATH)");
        }
        keys.push_back(std::move(k));
    }
    return keys;
}

// A scripted pause until another process creates `path` (2 minutes at most).
void waitForFile(const std::string& path) {
    const auto start = std::chrono::steady_clock::now();
    while (!fs::exists(path)) {
        if (std::chrono::steady_clock::now() - start > std::chrono::minutes(2))
            throw geometry::InputError("--keys wait=" + path + ": not created within 2 minutes");
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

bool heldKey(int key) {
    return key == GLFW_KEY_W || key == GLFW_KEY_A || key == GLFW_KEY_S || key == GLFW_KEY_D ||
           key == GLFW_KEY_Q || key == GLFW_KEY_E;
}

class App {
public:
    explicit App(const Options& opt) : mOpt(opt) {
        // Everything about the input is checked before a window opens.
        const gpu::MethodInfo& method = gpu::findMethod(opt.method);
        const std::vector<gpu::ParameterValue> given = apps::parseParameters(opt.parameters);
        gpu::resolveParameters(method, given);
        std::tie(mWidth, mHeight) = apps::parseSize(opt.size, "960x540");
        // The window's own bounds (the image rendered is --render-scale of it), narrower than
        // the renderer's: room for the panel, and no display is larger.
        constexpr int kMinWindowSide = 64, kMaxWindowSide = 8192;
        if (mWidth < kMinWindowSide || mHeight < kMinWindowSide || mWidth > kMaxWindowSide ||
            mHeight > kMaxWindowSide)
            throw geometry::InputError("--size: each side of the viewer's window must be between " +
                                       std::to_string(kMinWindowSide) + " and " +
                                       std::to_string(kMaxWindowSide) + ", got '" + opt.size + "'");
        apps::checkSamples(opt.samples);
        if (opt.frames < 0 || opt.frames > 1000000)
            throw geometry::InputError("--frames must be between 0 and 1000000");
        if (!(opt.renderScale >= 0.125f && opt.renderScale <= 1.0f))
            throw geometry::InputError("--render-scale must be between 0.125 and 1");
        mRenderScale = opt.renderScale;
        if (opt.legFrames < 1) throw geometry::InputError("--leg-frames must be at least 1");
        if (!opt.screenshot.empty() && opt.frames == 0)
            throw geometry::InputError("--screenshot needs --frames N (the frame to capture)");
        if ((!opt.report.empty() || !opt.visibility.empty()) && opt.frames == 0)
            throw geometry::InputError("--report and --visibility need --frames N");
        for (const std::string& out : {opt.screenshot, opt.report, opt.visibility}) {
            if (out.empty()) continue;
            const fs::path p(out);
            if (fs::is_directory(p)) throw geometry::InputError(out + ": is a directory");
            const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
            if (!fs::is_directory(dir))
                throw geometry::InputError(out + ": folder " + dir.string() + " does not exist");
        }
        if (opt.file.empty() == opt.scenePath.empty())
            throw geometry::InputError(
                "give one scene: a .glb/.gltf file, or --scene FILE.json");
        mKeys = parseKeys(opt.keys);
        if (!mKeys.empty() && opt.frames == 0)
            throw geometry::InputError("--keys needs --frames N");
        mSettings.debugView = gpu::findDebugView(opt.debugView).view;
        mSettings.method = std::string(method.name);
        mSettings.parameters = given;
        mSettings.samples = opt.samples;
        mSettings.waitForGpu = false;
        mAnimateLight = opt.animateLight;
        mShowPanel = !opt.hideUi;
        mShowOverlay = !opt.hideUi;

        mScene = std::make_unique<geometry::Scene>(
            geometry::loadScene(opt.file.empty() ? opt.scenePath : opt.file));
        mSimplified = apps::applySimplify(*mScene, opt.simplify);
        mViews = sceneViews(*mScene);
        if (opt.camera < 0 || opt.camera >= static_cast<int>(mViews.size()))
            throw geometry::InputError("--camera " + std::to_string(opt.camera) + ": " +
                                       (opt.file.empty() ? opt.scenePath : opt.file) + " has " +
                                       std::to_string(mViews.size()) + " view(s), 0.." +
                                       std::to_string(mViews.size() - 1));
        mViewIndex = opt.camera;
    }

    ~App() {
        if (mImGui) {
            ImGui_ImplOpenGL3_Shutdown();
            ImGui_ImplGlfw_Shutdown();
            ImGui::DestroyContext();
        }
        mRenderer.reset(); // GL objects go before the context
        mShaders.reset();
    }

    int run();

private:
    void openWindow();
    void resetSceneState();
    void loadDropped(const std::string& path);
    void handleInput(float seconds);
    geometry::Camera currentCamera() const;
    void renderScene();
    void drawPanel();
    void drawOverlay();
    void screenshot(const fs::path& path);
    void reloadShaders();
    void goToView(int index);
    void hangLamp(); // a lamp under the ceiling above what the camera looks at (H)

    static App& self(GLFWwindow* w) { return *static_cast<App*>(glfwGetWindowUserPointer(w)); }
    static void onKey(GLFWwindow* w, int key, int, int action, int mods);
    static void onScroll(GLFWwindow* w, double, double dy);
    static void onDrop(GLFWwindow* w, int count, const char** paths);

    Options mOpt;
    int mWidth = 960, mHeight = 540;
    std::unique_ptr<geometry::Scene> mScene;
    std::vector<View> mViews;
    int mViewIndex = 0;

    std::unique_ptr<gpu::GlfwContext> mContext;
    std::string mRendererName;
    std::unique_ptr<gpu::ShaderLoader> mShaders;
    std::unique_ptr<gpu::Renderer> mRenderer;
    bool mImGui = false;

    gpu::RenderSettings mSettings;
    gpu::FrameStats mStats;
    std::vector<gpu::PassTime> mShownGpu; // the newest completed GPU times
    double mShownGpuFrameMs = 0.0;
    int mShownGpuLag = -1;

    FlyCamera mFly;
    OrbitCamera mOrbit;
    bool mOrbitMode = false;
    LightRig mRig, mSceneRig;
    bool mLightEdited = false;
    bool mLampAtView = false; // hang a lamp at each glTF camera the viewer goes to
    std::unique_ptr<geometry::RayTracer> mTracer; // for hangLamp, built on first use
    bool mAnimateLight = false;
    float mLightTime = 0.0f;
    std::optional<geometry::RectLight> mLastGoodLight;
    std::optional<geometry::RectLight> mRefusedLight;
    std::string mStartView; // for the report: the view the run started at
    apps::SimplifyApplied mSimplified; // --simplify on the scene shown (the last loaded)

    bool mShowPanel = true, mShowOverlay = true;
    float mRenderScale = 1.0f;
    std::string mRenderError;  // the last frame's refusal (input), shown until a frame succeeds
    std::string mShaderError;  // the last failed reload
    std::string mStatus;       // last action (screenshot written, scene loaded, ...)
    std::string mPendingDrop;
    bool mScreenshotRequested = false;
    bool mReloadRequested = false;

    std::vector<ScriptedKey> mKeys;
    std::vector<int> mHeld; // scripted keys held this frame
    void setStatus(std::string text) {
        if (mOpt.frames > 0 && text != mStatus) std::printf("  frame %d: %s\n", mFrame, text.c_str());
        mStatus = std::move(text);
    }
    std::deque<double> mLoopMs; // wall clock per loop iteration, the last 120
    std::vector<double> mAllLoopMs, mAllGpuMs; // automation report
    double mLastMouseX = 0.0, mLastMouseY = 0.0;
    int mFrame = 0;
};

void App::openWindow() {
    // GLFW reports a missing display only from glfwInit; say plainly what is needed instead.
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!display || !*display) && (!wayland || !*wayland))
        throw gpu::ContextError(
            "no display: DISPLAY and WAYLAND_DISPLAY are unset. The viewer needs a window; "
            "run it under Xvfb for scripted captures (xvfb-run -a penumbra-viewer ...), or use "
            "penumbra-render for headless images");
    mContext = std::make_unique<gpu::GlfwContext>(
        gpu::GlfwContextDesc{.width = mWidth, .height = mHeight, .title = "penumbra-viewer"});
    mRendererName = mContext->info().renderer;
    GLFWwindow* w = mContext->window();
    glfwSetWindowUserPointer(w, this);
    // Ours first: ImGui chains to callbacks installed before it.
    glfwSetKeyCallback(w, onKey);
    glfwSetScrollCallback(w, onScroll);
    glfwSetDropCallback(w, onDrop);
    glfwSwapInterval(mOpt.frames > 0 ? 0 : 1);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini left in the working directory
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(w, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
    mImGui = true;
}

void App::resetSceneState() {
    mViews = sceneViews(*mScene);
    mViewIndex = std::clamp(mViewIndex, 0, static_cast<int>(mViews.size()) - 1);
    mFly = FlyCamera::fromCamera(mViews[static_cast<std::size_t>(mViewIndex)].camera);
    const geometry::Aabb b = mScene->bounds();
    const float diagonal = b.empty() ? 1.0f : glm::length(b.extent());
    mFly.speed = std::max(0.05f * diagonal, 0.1f); // crosses the scene in ~20 s
    mOrbit = OrbitCamera::around(mFly, 0.15f * diagonal);
    mSceneRig = mRig = LightRig::fromLight(mScene->light);
    mLightEdited = false;
    mLastGoodLight.reset();
    mRenderError.clear();
    mTracer.reset();
    mLampAtView = !mScene->cameras.empty() && !mOpt.sceneLight;
    if (mLampAtView) hangLamp();
}

void App::goToView(int index) {
    mViewIndex = index;
    const float speed = mFly.speed;
    mFly = FlyCamera::fromCamera(mViews[static_cast<std::size_t>(index)].camera);
    mFly.speed = speed;
    mOrbitMode = false;
    if (mLampAtView) hangLamp();
}

void App::hangLamp() {
    if (!mTracer) mTracer = std::make_unique<geometry::RayTracer>(*mScene);
    const std::optional<geometry::RectLight> lamp = lampAhead(*mScene, *mTracer, currentCamera());
    if (!lamp) {
        setStatus("no ceiling above this view to hang a lamp under; the light stays");
        return;
    }
    mRig = LightRig::fromLight(*lamp);
    mLightEdited = true;
    setStatus("lamp hung at " + std::to_string(lamp->center.x) + " " +
              std::to_string(lamp->center.y) + " " + std::to_string(lamp->center.z));
}

void App::loadDropped(const std::string& path) {
    try {
        auto scene = std::make_unique<geometry::Scene>(geometry::loadScene(path));
        const apps::SimplifyApplied simplified = apps::applySimplify(*scene, mOpt.simplify);
        auto renderer = std::make_unique<gpu::Renderer>(*scene, *mShaders);
        mSimplified = simplified;
        mTracer.reset();                 // built on the old scene
        mRenderer = std::move(renderer); // the old renderer refers to the old scene: it goes first
        mScene = std::move(scene);
        mViewIndex = 0;
        resetSceneState();
        setStatus("loaded " + path +
                  (mSimplified.visibilityError > 0.0f ? "; " + apps::simplifySummary(mSimplified) : ""));
    } catch (const std::exception& e) {
        setStatus(std::string("could not load ") + path + ": " + e.what());
    }
}

geometry::Camera App::currentCamera() const { return mOrbitMode ? mOrbit.camera() : mFly.camera(); }

void App::onKey(GLFWwindow* w, int key, int, int action, int mods) {
    App& app = self(w);
    if (action != GLFW_PRESS) return;
    if (key == GLFW_KEY_ESCAPE) {
        glfwSetWindowShouldClose(w, GLFW_TRUE);
        return;
    }
    if (app.mImGui && ImGui::GetIO().WantCaptureKeyboard) return; // typing into the panel
    switch (key) {
    case GLFW_KEY_F1: app.mShowOverlay = !app.mShowOverlay; break;
    case GLFW_KEY_TAB: app.mShowPanel = !app.mShowPanel; break;
    case GLFW_KEY_F12:
    case GLFW_KEY_P: app.mScreenshotRequested = true; break;
    case GLFW_KEY_R: app.mReloadRequested = true; break;
    case GLFW_KEY_O:
        app.mOrbitMode = !app.mOrbitMode;
        if (app.mOrbitMode) {
            app.mOrbit = OrbitCamera::around(app.mFly, app.mOrbit.distance);
        } else {
            const float speed = app.mFly.speed;
            app.mFly = FlyCamera::fromCamera(app.mOrbit.camera());
            app.mFly.speed = speed;
        }
        break;
    case GLFW_KEY_L: app.mAnimateLight = !app.mAnimateLight; break;
    case GLFW_KEY_V: { // next (Shift: previous) debug view
        const auto views = gpu::debugViews();
        const int n = static_cast<int>(views.size());
        int i = 0;
        while (i < n && views[static_cast<std::size_t>(i)].view != app.mSettings.debugView) ++i;
        i = (i + ((mods & GLFW_MOD_SHIFT) ? n - 1 : 1)) % n;
        app.mSettings.debugView = views[static_cast<std::size_t>(i)].view;
        break;
    }
    case GLFW_KEY_C: {
        const int n = static_cast<int>(app.mViews.size());
        app.goToView((app.mViewIndex + ((mods & GLFW_MOD_SHIFT) ? n - 1 : 1)) % n);
        break;
    }
    case GLFW_KEY_H: app.hangLamp(); break;
    default: break;
    }
}

void App::onScroll(GLFWwindow* w, double, double dy) {
    App& app = self(w);
    if (app.mImGui && ImGui::GetIO().WantCaptureMouse) return;
    const float factor = std::pow(1.2f, static_cast<float>(dy));
    if (app.mOrbitMode)
        app.mOrbit.zoom(1.0f / factor);
    else
        app.mFly.speed = std::clamp(app.mFly.speed * factor, 1e-3f, 1e4f);
}

void App::onDrop(GLFWwindow* w, int count, const char** paths) {
    if (count > 0) self(w).mPendingDrop = paths[0];
}

void App::handleInput(float seconds) {
    GLFWwindow* w = mContext->window();
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(w, &x, &y);
    const float dx = static_cast<float>(x - mLastMouseX), dy = static_cast<float>(y - mLastMouseY);
    mLastMouseX = x;
    mLastMouseY = y;
    const ImGuiIO& io = ImGui::GetIO();
    const float radiansPerPixel = 0.004f;
    if (!io.WantCaptureMouse) {
        if (mOrbitMode && (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS ||
                           glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS))
            mOrbit.rotate(-dx * radiansPerPixel, dy * radiansPerPixel);
        else if (!mOrbitMode && glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS)
            mFly.look(-dx * radiansPerPixel, -dy * radiansPerPixel);
    }
    if (io.WantCaptureKeyboard || mOrbitMode) return;
    auto down = [&](int key) {
        return glfwGetKey(w, key) == GLFW_PRESS ||
                       std::find(mHeld.begin(), mHeld.end(), key) != mHeld.end()
                   ? 1.0f
                   : 0.0f;
    };
    const glm::vec3 local(down(GLFW_KEY_D) - down(GLFW_KEY_A), down(GLFW_KEY_E) - down(GLFW_KEY_Q),
                          down(GLFW_KEY_W) - down(GLFW_KEY_S));
    const float boost = (glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS) ? 4.0f : 1.0f;
    if (local != glm::vec3(0.0f)) mFly.move(local, seconds * boost);
}

void App::renderScene() {
    int fbw = 0, fbh = 0;
    glfwGetFramebufferSize(mContext->window(), &fbw, &fbh);
    mSettings.width = std::max(static_cast<int>(std::lround(fbw * mRenderScale)), 1);
    mSettings.height = std::max(static_cast<int>(std::lround(fbh * mRenderScale)), 1);
    mSettings.camera = currentCamera();
    std::optional<geometry::RectLight> requested; // the rig's, when it replaces the scene's
    if (mAnimateLight)
        requested = mRig.animated(mLightTime, std::max(mRig.halfU, mRig.halfV));
    else if (mLightEdited)
        requested = mRig.light();
    if (mRefusedLight && requested != mRefusedLight) mRefusedLight.reset(); // changed: try it
    std::optional<geometry::RectLight> light = requested;
    // A light the renderer refused (it touches geometry) is not tried again until it changes:
    // the last clear light is shown meanwhile, and the panel says why.
    if (mRefusedLight) light = mLastGoodLight;
    mSettings.light = light;
    try {
        mStats = mRenderer->renderFrame(mSettings);
        if (light) mLastGoodLight = light;
        if (!mRefusedLight) mRenderError.clear();
    } catch (const geometry::InputError& e) {
        const bool lightRefused =
            light && dynamic_cast<const geometry::LightRefusedError*>(&e) != nullptr;
        if (mOpt.frames > 0 && !lightRefused) throw; // scripted: no silent fallback
        mRenderError = e.what();
        if (lightRefused) {
            setStatus("light refused, the last clear light stays: " + mRenderError);
            mRefusedLight = light;
            mSettings.light = mLastGoodLight;
            try {
                mStats = mRenderer->renderFrame(mSettings);
            } catch (const std::exception& again) {
                mRenderError += std::string("\n") + again.what();
            }
        }
    } catch (const std::exception& e) {
        // A program that fails to compile when a method or view is first used (shaders edited
        // on disk), a GL error: shown, the last image stays; scripted runs stop on it (exit 1).
        if (mOpt.frames > 0) throw;
        mRenderError = e.what();
    }
    if (mStats.gpuTimesLag >= 0) {
        mShownGpu = mStats.gpu;
        mShownGpuFrameMs = mStats.gpuFrameMs;
        mShownGpuLag = mStats.gpuTimesLag;
    }
}

void App::screenshot(const fs::path& path) {
    int w = 0, h = 0;
    glfwGetFramebufferSize(mContext->window(), &w, &h);
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w) * h * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    const std::size_t row = static_cast<std::size_t>(w) * 4;
    for (int y = 0; y < h / 2; ++y)
        std::swap_ranges(rgba.begin() + y * row, rgba.begin() + (y + 1) * row,
                         rgba.begin() + (h - 1 - y) * row);
    for (std::size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255; // the window is opaque
    geometry::writePng(path, w, h, 4, rgba.data());
    setStatus("wrote " + path.string());
}

void App::reloadShaders() {
    // A new loader and renderer, tried on this frame's settings; on any error the running one
    // (its programs known good) stays and the message is shown.
    try {
        auto shaders = std::make_unique<gpu::ShaderLoader>(gpu::defaultShaderDir());
        auto renderer = std::make_unique<gpu::Renderer>(*mScene, *shaders);
        renderer->renderFrame(mSettings);
        mRenderer = std::move(renderer);
        mShaders = std::move(shaders);
        mShaderError.clear();
        setStatus("shaders reloaded from " + gpu::defaultShaderDir().string());
    } catch (const std::exception& e) {
        mShaderError = e.what();
        setStatus(std::string("shader reload failed, keeping the previous programs: ") + e.what());
    }
}

void App::drawOverlay() {
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.55f);
    // Fixed width, height fitted to the content each frame (0 = auto): a long debug note wraps.
    ImGui::SetNextWindowSize(ImVec2(ImGui::GetFontSize() * 26.0f, 0.0f), ImGuiCond_Always);
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration |
                                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav |
                                   ImGuiWindowFlags_NoInputs;
    if (ImGui::Begin("##overlay", nullptr, flags)) {
        const double ms = apps::median({mLoopMs.begin(), mLoopMs.end()}, 0.0);
        ImGui::Text("%s  %dx%d", mSettings.method.c_str(), mSettings.width, mSettings.height);
        ImGui::Text("%.1f fps  frame %.1f ms  GPU %.1f ms", ms > 0 ? 1000.0 / ms : 0.0, ms,
                    mShownGpuFrameMs);
        ImGui::Text("%s%s", mOrbitMode ? "orbit" : "fly",
                    mAnimateLight ? "  light animated" : "");
        ImGui::TextUnformatted(mRendererName.c_str());
        if (mSettings.debugView != gpu::DebugView::Shaded) {
            ImGui::TextWrapped("%s", mStats.debugNote.c_str());
        }
        if (!mRenderError.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "render refused");
    }
    ImGui::End();
}

void App::drawPanel() {
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(ImVec2(vp->WorkSize.x - 8, 8), ImGuiCond_FirstUseEver, ImVec2(1, 0));
    ImGui::SetNextWindowSize(ImVec2(std::min(340.0f, 0.45f * vp->WorkSize.x), vp->WorkSize.y - 16),
                             ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.85f);
    if (!ImGui::Begin("penumbra")) {
        ImGui::End();
        return;
    }
    const ImVec4 red(1.0f, 0.45f, 0.45f, 1.0f);
    ImGui::TextWrapped("%s", mRendererName.c_str());
    if (!mStatus.empty()) ImGui::TextWrapped("%s", mStatus.c_str());
    if (!mRenderError.empty()) ImGui::TextColored(red, "%s", mRenderError.c_str());
    if (!mShaderError.empty()) {
        ImGui::TextColored(red, "shader reload failed (R to retry):");
        ImGui::TextWrapped("%s", mShaderError.c_str());
    }

    // Method and its parameters.
    if (ImGui::CollapsingHeader("Method", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (ImGui::BeginCombo("method", mSettings.method.c_str())) {
            for (const gpu::MethodInfo& m : gpu::methodTable()) {
                if (!m.implemented()) continue;
                const bool selected = m.name == mSettings.method;
                if (ImGui::Selectable(std::string(m.name).c_str(), selected)) {
                    mSettings.method = std::string(m.name);
                    mSettings.parameters.clear();
                }
                if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", std::string(m.summary).c_str());
            }
            ImGui::EndCombo();
        }
        const gpu::MethodInfo& info = gpu::findMethod(mSettings.method);
        const auto resolved = gpu::resolveParameters(info, mSettings.parameters);
        for (const gpu::MethodParameter& p : info.parameters) {
            const std::string current(gpu::parameterValue(resolved, p.name));
            const std::string label(p.name);
            if (ImGui::BeginCombo(label.c_str(), current.c_str())) {
                for (std::string_view v : p.values) {
                    if (ImGui::Selectable(std::string(v).c_str(), v == current)) {
                        auto it = std::find_if(mSettings.parameters.begin(), mSettings.parameters.end(),
                                               [&](const auto& pv) { return pv.name == p.name; });
                        if (it == mSettings.parameters.end())
                            mSettings.parameters.push_back({label, std::string(v)});
                        else
                            it->value = std::string(v);
                    }
                }
                ImGui::EndCombo();
            }
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", std::string(p.help).c_str());
        }
        if (info.usesSamples) ImGui::SliderInt("samples", &mSettings.samples, 1, 1024);
    }

    if (ImGui::CollapsingHeader("Debug view", ImGuiTreeNodeFlags_DefaultOpen)) {
        const gpu::DebugViewInfo& current = gpu::debugViewInfo(mSettings.debugView);
        if (ImGui::BeginCombo("view", std::string(current.name).c_str())) {
            for (const gpu::DebugViewInfo& v : gpu::debugViews()) {
                if (ImGui::Selectable(std::string(v.name).c_str(), v.view == mSettings.debugView))
                    mSettings.debugView = v.view;
                if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", std::string(v.help).c_str());
            }
            ImGui::EndCombo();
        }
        if (mSettings.debugView == gpu::DebugView::GroupParts)
            ImGui::InputInt("group", &mSettings.debugGroup);
        if (mSettings.debugView == gpu::DebugView::ErrorHeatMap) {
            ImGui::SliderInt("reference samples", &mSettings.samples, 16, 4096, "%d",
                             ImGuiSliderFlags_Logarithmic);
            ImGui::SliderInt("samples per frame", &mSettings.referenceSamplesPerFrame, 1, 64);
            ImGui::SliderFloat("error scale", &mSettings.errorScale, 0.01f, 1.0f, "%.2f");
        }
        if (!mStats.debugNote.empty()) ImGui::TextWrapped("%s", mStats.debugNote.c_str());
    }

    if (ImGui::CollapsingHeader("Camera", ImGuiTreeNodeFlags_DefaultOpen)) {
        const std::string& name = mViews[static_cast<std::size_t>(mViewIndex)].name;
        if (ImGui::BeginCombo("view (C)", name.c_str())) {
            for (std::size_t i = 0; i < mViews.size(); ++i)
                if (ImGui::Selectable(mViews[i].name.c_str(), static_cast<int>(i) == mViewIndex))
                    goToView(static_cast<int>(i));
            ImGui::EndCombo();
        }
        bool orbit = mOrbitMode;
        if (ImGui::Checkbox("orbit (O)", &orbit) && orbit != mOrbitMode) {
            mOrbitMode = orbit;
            if (orbit) mOrbit = OrbitCamera::around(mFly, mOrbit.distance);
            else {
                const float speed = mFly.speed;
                mFly = FlyCamera::fromCamera(mOrbit.camera());
                mFly.speed = speed;
            }
        }
        ImGui::SliderFloat("speed m/s", &mFly.speed, 0.01f, 100.0f, "%.2f",
                           ImGuiSliderFlags_Logarithmic);
        const geometry::Camera c = currentCamera();
        ImGui::Text("eye %.2f %.2f %.2f", c.eye.x, c.eye.y, c.eye.z);
    }

    if (ImGui::CollapsingHeader("Light", ImGuiTreeNodeFlags_DefaultOpen)) {
        bool changed = false;
        changed |= ImGui::DragFloat3("centre", &mRig.center.x, 0.01f * std::max(mFly.speed, 0.1f));
        changed |= ImGui::DragFloat("half-width u", &mRig.halfU, 0.005f, 1e-4f, 100.0f, "%.3f",
                                    ImGuiSliderFlags_Logarithmic);
        changed |= ImGui::DragFloat("half-width v", &mRig.halfV, 0.005f, 1e-4f, 100.0f, "%.3f",
                                    ImGuiSliderFlags_Logarithmic);
        changed |= ImGui::SliderFloat("yaw", &mRig.yawDeg, -180.0f, 180.0f, "%.1f deg");
        changed |= ImGui::SliderFloat("pitch", &mRig.pitchDeg, -89.0f, 89.0f, "%.1f deg");
        changed |= ImGui::SliderFloat("roll", &mRig.rollDeg, -180.0f, 180.0f, "%.1f deg");
        if (changed) mLightEdited = true;
        ImGui::Checkbox("animate (L)", &mAnimateLight);
        ImGui::SameLine();
        if (ImGui::Button("scene light")) {
            mRig = mSceneRig;
            mLightEdited = false;
            mLampAtView = false;
        }
        ImGui::SameLine();
        if (ImGui::Button("lamp here (H)")) hangLamp();
        ImGui::Checkbox("lamp at each view", &mLampAtView);
        const geometry::RectLight l = mSettings.light ? *mSettings.light : mScene->light;
        ImGui::Text("area %.4f m^2", 4.0f * glm::length(glm::cross(l.u, l.v)));
    }

    if (ImGui::CollapsingHeader("Frame", ImGuiTreeNodeFlags_DefaultOpen)) {
        const double ms = apps::median({mLoopMs.begin(), mLoopMs.end()}, 0.0);
        ImGui::Text("%.1f fps, %.2f ms per frame (median of %zu)", ms > 0 ? 1000.0 / ms : 0.0, ms,
                    mLoopMs.size());
        ImGui::SliderFloat("render scale", &mRenderScale, 0.125f, 1.0f, "%.3f");
        ImGui::Text("rendering %dx%d; renderer CPU (submit) %.2f ms", mSettings.width,
                    mSettings.height, mStats.frameMs);
        if (mShownGpuLag >= 0)
            ImGui::Text("GPU frame %.2f ms (%d frame%s ago)", mShownGpuFrameMs, mShownGpuLag,
                        mShownGpuLag == 1 ? "" : "s");
        if (ImGui::BeginTable("passes", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) {
            for (const auto& p : mShownGpu) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::Text("GPU %s", p.name.c_str());
                ImGui::TableNextColumn();
                ImGui::Text("%.2f ms", p.ms);
            }
            for (const auto& c : mStats.cpu) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::Text("CPU %s", c.name.c_str());
                ImGui::TableNextColumn();
                ImGui::Text("%.2f ms", c.ms);
            }
            ImGui::EndTable();
        }
    }

    if (ImGui::CollapsingHeader("Counts", ImGuiTreeNodeFlags_DefaultOpen)) {
        ImGui::Text("triangles %zu", mStats.triangles);
        if (mSimplified.visibilityError > 0.0f)
            ImGui::TextWrapped("stand-ins (--simplify %g, for the light at load): %zu meshes, "
                               "%zu -> %zu triangles",
                               double(mSimplified.visibilityError), mSimplified.stats.meshes,
                               mSimplified.stats.trianglesBefore, mSimplified.stats.trianglesAfter);
        ImGui::Text("silhouette groups %zu, edges %zu", mStats.silhouetteGroups,
                    mStats.silhouetteEdges);
        ImGui::Text("shadow-volume triangles %zu", mStats.volumeTriangles);
        for (const auto& c : mStats.counters) ImGui::Text("%s %.0f", c.name.c_str(), c.value);
        for (const auto& choice : mStats.objectChoices)
            ImGui::TextWrapped("object %zu: %s (%s)", choice.object, choice.path.c_str(),
                               choice.reason.c_str());
    }
    ImGui::TextDisabled("WASD QE fly, right mouse look, wheel speed, O orbit, C next view,");
    ImGui::TextDisabled("L light animation, H lamp here, V debug view, F1 overlay, Tab panel,");
    ImGui::TextDisabled("F12/P screenshot,");
    ImGui::TextDisabled("R reload shaders, Esc quit; drop a .glb to open it");
    ImGui::End();
}

int App::run() {
    openWindow();
    mShaders = std::make_unique<gpu::ShaderLoader>(gpu::defaultShaderDir());
    mRenderer = std::make_unique<gpu::Renderer>(*mScene, *mShaders);
    resetSceneState();
    mStartView = mViews[static_cast<std::size_t>(mViewIndex)].name;
    if (mOpt.frames > 0)
        std::printf("penumbra-viewer: %s, %s, %dx%d (render scale %.3g), view '%s'\n  renderer: %s\n  CPU: %s\n",
                    (mOpt.file.empty() ? mOpt.scenePath : mOpt.file).c_str(),
                    mSettings.method.c_str(), mWidth, mHeight, mRenderScale,
                    mViews[static_cast<std::size_t>(mViewIndex)].name.c_str(),
                    mRendererName.c_str(), apps::cpuModel().c_str());
    if (mOpt.frames > 0 && mSimplified.visibilityError > 0.0f)
        std::printf("  %s\n", apps::simplifySummary(mSimplified).c_str());
    std::fflush(stdout); // scripts watch for this line

    GLFWwindow* window = mContext->window();
    auto last = std::chrono::steady_clock::now();
    glfwGetCursorPos(window, &mLastMouseX, &mLastMouseY);
    while (!glfwWindowShouldClose(window)) {
        const auto now = std::chrono::steady_clock::now();
        const double loopMs = std::chrono::duration<double, std::milli>(now - last).count();
        last = now;
        if (mFrame > 0) {
            mLoopMs.push_back(loopMs);
            if (mLoopMs.size() > 120) mLoopMs.pop_front();
            mAllLoopMs.push_back(loopMs);
        }
        // Scripted runs step time by a fixed 1/30 s so that captures repeat exactly.
        const float seconds =
            mOpt.frames > 0 ? 1.0f / 30.0f : static_cast<float>(std::min(loopMs, 100.0) * 1e-3);

        glfwPollEvents();
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        mHeld.clear();
        for (const ScriptedKey& k : mKeys) {
            if (k.frame != mFrame) continue;
            if (!k.wait.empty()) {
                std::printf("  frame %d: waiting for %s\n", mFrame, k.wait.c_str());
                std::fflush(stdout);
                waitForFile(k.wait);
            }
            else if (!k.drop.empty())
                mPendingDrop = k.drop;
            else if (heldKey(k.key))
                mHeld.push_back(k.key);
            else
                onKey(window, k.key, 0, GLFW_PRESS, 0);
        }
        if (!mPendingDrop.empty()) {
            loadDropped(mPendingDrop);
            mPendingDrop.clear();
        }
        handleInput(seconds);
        if (mOpt.flyThrough) {
            std::vector<geometry::Camera> tour; // the views of the scene shown now (drops change it)
            for (const View& v : mViews) tour.push_back(v.camera);
            mFly = FlyCamera::fromCamera(flyThrough(tour, mFrame, mOpt.legFrames));
            mOrbitMode = false;
        }
        if (mAnimateLight) mLightTime += seconds;

        if (mReloadRequested) {
            mReloadRequested = false;
            reloadShaders();
        }
        renderScene();

        int fbw = 0, fbh = 0;
        glfwGetFramebufferSize(window, &fbw, &fbh);
        gpu::applyState(gpu::PipelineState{}); // whatever a pass (or a failed one) left
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, fbw, fbh);
        glClearColor(0.05f, 0.05f, 0.06f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        mRenderer->blitImage(0, 0, fbw, fbh);
        if (mShowOverlay) drawOverlay();
        if (mShowPanel) drawPanel();
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        gpu::checkGl("viewer frame");
        if (mShownGpuLag >= 0 && mStats.gpuTimesLag >= 0) mAllGpuMs.push_back(mShownGpuFrameMs);

        const bool lastFrame = mOpt.frames > 0 && mFrame + 1 >= mOpt.frames;
        if (lastFrame && !mOpt.screenshot.empty()) screenshot(mOpt.screenshot);
        if (lastFrame && !mOpt.visibility.empty())
            geometry::writePfm(mOpt.visibility, mRenderer->visibility());
        if (mScreenshotRequested) {
            mScreenshotRequested = false;
            screenshot(timestampedName());
        }
        mContext->swapBuffers();
        char title[256];
        std::snprintf(title, sizeof title, "penumbra-viewer — %s — %.1f fps", mSettings.method.c_str(),
                      mLoopMs.empty() ? 0.0
                                      : 1000.0 / apps::median({mLoopMs.begin(), mLoopMs.end()}));
        glfwSetWindowTitle(window, title);
        ++mFrame;
        if (lastFrame) break;
    }

    if (mOpt.frames > 0 && mFrame < mOpt.frames)
        std::printf("  quit (Esc) at frame %d of %d%s\n", mFrame, mOpt.frames,
                    mOpt.screenshot.empty() ? "" : ": no screenshot written");
    if (mOpt.frames > 0) {
        glFinish();
        const double ms = apps::median(mAllLoopMs, 0.0);
        const double gpuMs = apps::median(mAllGpuMs, 0.0);
        std::printf("  %d frames: median frame %.2f ms (%.1f fps), GPU frame %.2f ms\n", mFrame, ms,
                    ms > 0 ? 1000.0 / ms : 0.0, gpuMs);
        if (!mOpt.screenshot.empty() && mFrame >= mOpt.frames)
            std::printf("  wrote %s\n", mOpt.screenshot.c_str());
        if (!mOpt.report.empty()) {
            nlohmann::json r;
            r["scene"] = mOpt.file.empty() ? mOpt.scenePath : mOpt.file;
            r["method"] = mSettings.method;
            r["size"] = {mWidth, mHeight};
            r["render_size"] = {mSettings.width, mSettings.height};
            r["view"] = mStartView;
            r["fly_through"] = mOpt.flyThrough;
            r["animate_light"] = mOpt.animateLight;
            r["frames"] = mFrame;
            r["frame_ms_median"] = ms;
            r["fps"] = ms > 0 ? 1000.0 / ms : 0.0;
            r["gpu_frame_ms_median"] = gpuMs;
            r["triangles"] = mStats.triangles;
            r["simplify"] = apps::simplifyJson(mSimplified);
            // The last frame's counts and stages (GPU passes as last read from the timer ring).
            nlohmann::json last;
            for (const gpu::Counter& c : mStats.counters) last["counters"][c.name] = c.value;
            for (const gpu::CpuTime& c : mStats.cpu) last["cpu_ms"][c.name] = c.ms;
            std::map<std::string, double> passes; // a pass run per batch is summed
            for (const gpu::PassTime& p : mShownGpu) passes[p.name] += p.ms;
            for (const auto& [name, ms] : passes) last["gpu_ms"][name] = ms;
            last["silhouette_edges"] = mStats.silhouetteEdges;
            last["silhouette_groups"] = mStats.silhouetteGroups;
            r["last_frame"] = last;
            r["gl_renderer"] = mRendererName;
            r["cpu"] = apps::cpuModel();
            apps::writeJsonFile(mOpt.report, r);
        }
    }
    return 0;
}

} // namespace

int run(const Options& options) {
    App app(options);
    return app.run();
}

} // namespace viewer
