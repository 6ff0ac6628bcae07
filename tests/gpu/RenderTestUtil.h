// Helpers for GL tests that render whole scenes: load a data/ scene, render one frame with the
// Renderer, compare visibility maps, and write actual/expected/diff images on failure.
#pragma once

#include <geometry/scene/ImageIO.h>
#include <geometry/scene/Primitives.h>
#include <geometry/scene/Scene.h>
#include <geometry/shadow/OcclusionSlices.h>
#include <geometry/reference/Framing.h>
#include <gpu/Renderer.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <bit>
#include <optional>
#include <string>
#include <vector>

namespace testutil {

inline std::filesystem::path dataPath(const std::string& name) {
    return std::filesystem::path(PENUMBRA_SOURCE_DIR) / "data" / name;
}

inline std::filesystem::path sharedPath(const std::string& name) {
    return std::filesystem::path(PENUMBRA_SHARED_DIR) / name;
}

// A thin wall (one quad in the plane z = 0, front towards +z) and the ground, beside a light
// whose plane the wall's plane cuts: about half the light lies behind the wall's plane. The
// own-plane tests' scene (validateScene is the caller's, after adding objects).
inline geometry::Scene wallBesideLight() {
    geometry::Scene scene;
    scene.camera = {{6.0f, 3.0f, 6.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    scene.light = {{3.8f, 2.0f, 0.1f}, {0.6f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.6f}};
    scene.objects.push_back({"wall", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 1.5f, 0}, {3, 0, 0}, {0, 1.5f, 0})});
    scene.objects.push_back({"ground", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 0, 0}, {4, 0, 0}, {0, 0, -4})});
    return scene;
}

// The light's centre exactly in the planes of two casters' faces, as a lamp hung at a level's
// grid coordinates puts it (oa_dm1's eighth spawn view): a thin wall (one quad, plane z = 0) to
// one side of the light and a pillar (a box) whose front face lies in the plane x = 1.5 of the
// centre. Every coordinate is exact in float.
inline geometry::Scene wallsThroughLightCentre() {
    geometry::Scene scene;
    scene.camera = {{6.0f, 3.0f, 6.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    scene.light = {{1.5f, 2.5f, 0.0f}, {0.5f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.5f}};
    scene.objects.push_back({"wall", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({-1.25f, 1.5f, 0}, {1.75f, 0, 0}, {0, 1.5f, 0})});
    scene.objects.push_back({"pillar", geometry::ShadowMethod::Auto,
                             geometry::makeBox({1.25f, 1.0f, 2.0f}, {0.5f, 2.0f, 0.5f})});
    scene.objects.push_back({"ground", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 0, 0}, {4, 0, 0}, {0, 0, -4})});
    return scene;
}

// On wallBesideLight's wall front (pixels with z = 0 above the ground), |V - the exact share of
// the light in front of the wall's plane|: the pixels, the largest difference, and the pixels
// off by more than 0.01.
struct WallFront {
    std::size_t pixels = 0, off = 0;
    double worst = 0.0;
};

inline WallFront wallFront(const geometry::Scene& scene, const geometry::FloatImage& visibility,
                           const geometry::FloatImage& position) {
    WallFront w;
    for (std::size_t i = 0; i < visibility.data.size(); ++i) {
        const glm::vec3 p(position.data[3 * i], position.data[3 * i + 1],
                          position.data[3 * i + 2]);
        if (!std::isfinite(p.x) || std::abs(p.z) > 1e-3f || p.y < 0.05f) continue;
        const float front = geometry::horizonFraction(scene.light, p, {0.0f, 0.0f, 1.0f});
        const double d = std::abs(visibility.data[i] - front);
        w.worst = std::max(w.worst, d);
        w.off += d > 0.01;
        ++w.pixels;
    }
    return w;
}

// A shared level (path under ../shared) with the automatic framed view instead of its first spawn
// camera: the view of `--scene level.glb` before glTF cameras were read, on which the level
// tests were measured. The light is loadScene's either way.
inline geometry::Scene framedLevel(const std::string& name) {
    geometry::Scene scene = geometry::loadScene(sharedPath(name));
    geometry::selectFramedCamera(scene);
    return scene;
}

struct Rendered {
    geometry::FloatImage visibility; // NaN where no surface
    geometry::FloatImage position;
    geometry::FloatImage normal;
    gpu::FrameStats stats;
};

// The settings of a frame of `method` at width x height; the others keep their defaults.
inline gpu::RenderSettings frameSettings(const std::string& method, int width, int height) {
    gpu::RenderSettings s;
    s.method = method;
    s.width = width;
    s.height = height;
    return s;
}

// A renderer of `scene` with the shaders of defaultShaderDir() (kept alive with it).
struct SceneRenderer {
    gpu::ShaderLoader shaders{gpu::defaultShaderDir()};
    gpu::Renderer renderer;
    explicit SceneRenderer(const geometry::Scene& scene) : renderer(scene, shaders) {}
};

// One frame of `scene` with settings `s` by a fresh renderer, and what it read back.
inline Rendered render(const geometry::Scene& scene, const gpu::RenderSettings& s) {
    SceneRenderer sr(scene);
    Rendered r;
    r.stats = sr.renderer.renderFrame(s);
    r.visibility = sr.renderer.visibility();
    r.position = sr.renderer.position();
    r.normal = sr.renderer.normal();
    return r;
}

inline Rendered render(const geometry::Scene& scene, const std::string& method, int width,
                       int height, int samples,
                       const std::vector<gpu::ParameterValue>& parameters = {}) {
    gpu::RenderSettings s = frameSettings(method, width, height);
    s.samples = samples;
    s.parameters = parameters;
    return render(scene, s);
}

inline Rendered render(const geometry::Scene& scene, const std::string& method, int size,
                       int samples = 256) {
    return render(scene, method, size, size, samples);
}

// What a frame's settings replace of the scene (RenderSettings::camera, ::light); nullopt: keep.
struct Override {
    std::optional<geometry::Camera> camera;
    std::optional<geometry::RectLight> light;
};

// V of a frame of `method` at 96² with 64 light samples and `o` applied to its settings, by a
// renderer whose first frame had the scene's own camera and light: the override must not reuse
// that frame's state.
inline geometry::FloatImage renderOverridden(const geometry::Scene& scene,
                                             const std::string& method, const Override& o) {
    SceneRenderer sr(scene);
    gpu::RenderSettings s = frameSettings(method, 96, 96);
    s.samples = 64;
    sr.renderer.renderFrame(s);
    s.camera = o.camera;
    s.light = o.light;
    sr.renderer.renderFrame(s);
    return sr.renderer.visibility();
}

// A shared level seen from its glTF camera `camera`, lit as the three programs light it there:
// the viewer's lamp (geometry::lightAtView). Fails the test if no lamp fits.
inline geometry::Scene levelWithLamp(const std::string& level, int camera) {
    geometry::Scene scene = geometry::loadScene(sharedPath("levels/" + level));
    geometry::selectCamera(scene, camera);
    const std::string light = geometry::lightAtView(scene, false);
    EXPECT_EQ(light, "lamp at the view") << level << " camera " << camera;
    return scene;
}

// Mean |dV| and pixels off by more than `tol`, over the pixels where both have a surface.
struct VisibilityDiff {
    double mean = 0.0;
    std::size_t off = 0, pixels = 0;
};

inline VisibilityDiff visibilityDiff(const geometry::FloatImage& a, const geometry::FloatImage& b,
                                     float tol) {
    VisibilityDiff d;
    for (std::size_t i = 0; i < a.data.size() && i < b.data.size(); ++i) {
        const float x = a.data[i], y = b.data[i];
        if (!std::isfinite(x) || !std::isfinite(y)) continue;
        d.mean += std::abs(x - y);
        d.off += std::abs(x - y) > tol;
        ++d.pixels;
    }
    if (d.pixels) d.mean /= static_cast<double>(d.pixels);
    return d;
}

// The value of a method's counter in a frame's stats; a failure if it has none.
inline double counter(const gpu::FrameStats& stats, const std::string& name) {
    for (const auto& c : stats.counters)
        if (c.name == name) return c.value;
    ADD_FAILURE() << "no counter " << name;
    return -1.0;
}

// A player's first view of a shared level: the glTF camera of one spawn point (eye and yaw
// copied from the node `spawn N` of the .glb; yaw 0 looks along -z, glTF's camera axis), with
// a small square light `ahead` metres in front of the eye and `up` metres above it.
struct SpawnView {
    const char* level; // file name under ../shared/levels
    const char* name;  // for messages and image names
    glm::vec3 eye;
    float yawDeg;
    float ahead, up, halfSize;
};

inline geometry::Scene spawnScene(const SpawnView& view) {
    geometry::Scene scene = geometry::loadScene(sharedPath(std::string("levels/") + view.level));
    const float yaw = glm::radians(view.yawDeg);
    const glm::vec3 forward(-std::sin(yaw), 0.0f, -std::cos(yaw));
    scene.camera.eye = view.eye;
    scene.camera.target = view.eye + forward;
    scene.camera.up = {0.0f, 1.0f, 0.0f};
    scene.camera.fovYDeg = 73.7397953f; // the levels' camera: yfov 1.2870022 rad
    scene.light.center = view.eye + view.ahead * forward + glm::vec3(0.0f, view.up, 0.0f);
    scene.light.u = {view.halfSize, 0.0f, 0.0f};
    scene.light.v = {0.0f, 0.0f, view.halfSize};
    geometry::validateScene(scene); // the light must touch nothing
    return scene;
}

// Surface pixels of `v` (rows top to bottom) whose V is not 1 - popcount / N of their mask in
// `masks` (Renderer::lightMasks: rows bottom to top).
inline std::size_t pixelsNotThePopcount(const geometry::FloatImage& v, const gpu::LightMasks& masks) {
    const int words = masks.samples / 32;
    std::size_t wrong = 0;
    for (int row = 0; row < masks.height; ++row)
        for (int x = 0; x < masks.width; ++x) {
            const float vv = v.data[std::size_t(row) * masks.width + x];
            if (!std::isfinite(vv)) continue;
            const std::size_t px = std::size_t(masks.height - 1 - row) * masks.width + x;
            int hidden = 0;
            for (int w = 0; w < words; ++w) hidden += std::popcount(masks.words[px * words + w]);
            wrong += vv != 1.0f - float(hidden) / float(masks.samples);
        }
    return wrong;
}

// Pixels where two visibility images differ: by more than `tol`, or surface in one only (NaN).
inline std::size_t countDiffering(const geometry::FloatImage& a, const geometry::FloatImage& b,
                                  float tol) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.data.size(); ++i) {
        const bool na = std::isnan(a.data[i]), nb = std::isnan(b.data[i]);
        if (na != nb || (!na && std::abs(a.data[i] - b.data[i]) > tol)) ++n;
    }
    return n;
}

inline glm::vec3 pixelPosition(const geometry::FloatImage& p, std::size_t i) {
    return {p.data[3 * i], p.data[3 * i + 1], p.data[3 * i + 2]};
}

// Writes <name>-actual.png, -expected.png and -diff.png (|difference| x 4, red) under
// <build>/test-output/ so that a failing comparison can be looked at.
inline void writeComparisonImages(const std::string& name, const geometry::FloatImage& actual,
                                  const std::vector<float>& expected) {
    const auto dir = std::filesystem::path(PENUMBRA_BIN_DIR) / ".." / "test-output";
    std::filesystem::create_directories(dir);
    const int w = actual.width, h = actual.height;
    std::vector<std::uint8_t> a(w * h * 3), e(w * h * 3), d(w * h * 3);
    auto grey = [](float v) {
        return std::isfinite(v) ? static_cast<std::uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f)
                                : std::uint8_t{40};
    };
    for (int i = 0; i < w * h; ++i) {
        const float va = actual.data[i], ve = expected[i];
        for (int c = 0; c < 3; ++c) {
            a[3 * i + c] = grey(va);
            e[3 * i + c] = grey(ve);
        }
        const float diff = std::isfinite(va) && std::isfinite(ve) ? std::fabs(va - ve) : 0.0f;
        d[3 * i] = static_cast<std::uint8_t>(std::clamp(diff * 4.0f, 0.0f, 1.0f) * 255.0f);
        d[3 * i + 1] = d[3 * i + 2] = 0;
    }
    geometry::writePng(dir / (name + "-actual.png"), w, h, 3, a.data());
    geometry::writePng(dir / (name + "-expected.png"), w, h, 3, e.data());
    geometry::writePng(dir / (name + "-diff.png"), w, h, 3, d.data());
}

} // namespace testutil
