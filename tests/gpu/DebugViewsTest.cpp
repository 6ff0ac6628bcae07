// Debug views (gpu/Renderer.h DebugView): every view renders on a small scene and a level with
// each real-time method; the views show what they claim (V bytes, the stencil count class
// against the hard method's V, a progressive reference equal to the `reference` method's V and
// errorHeatMap's colours of it); views a method cannot serve say so and show the shaded image.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"

#include <geometry/core/Error.h>
#include <geometry/reference/ErrorImage.h>
#include <geometry/reference/Framing.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

class DebugViews : public GlTest {};

using Image = std::vector<std::uint8_t>; // RGBA8, rows top to bottom

// lib/Debug.glsl kDebugNoSurface as bytes.
constexpr std::uint8_t kNoSurface[3] = {26, 36, 89};

struct Frame {
    Image image;
    geometry::FloatImage visibility;
    gpu::FrameStats stats;
};

Frame renderView(gpu::Renderer& renderer, gpu::RenderSettings s, gpu::DebugView view) {
    s.debugView = view;
    Frame f;
    f.stats = renderer.renderFrame(s);
    f.image = renderer.imageRgba8();
    f.visibility = renderer.visibility();
    return f;
}

gpu::RenderSettings settings(const std::string& method, int size) {
    gpu::RenderSettings s;
    s.method = method;
    s.width = s.height = size;
    s.samples = 64;
    return s;
}

std::size_t differingPixels(const Image& a, const Image& b) {
    std::size_t n = 0;
    for (std::size_t i = 0; i + 3 < a.size(); i += 4)
        n += a[i] != b[i] || a[i + 1] != b[i + 1] || a[i + 2] != b[i + 2];
    return n;
}

void writeImage(const std::string& name, const Image& image, int width, int height) {
    const auto dir = std::filesystem::path(PENUMBRA_BIN_DIR) / ".." / "test-output";
    std::filesystem::create_directories(dir);
    geometry::writePng(dir / (name + ".png"), width, height, 4, image.data());
}

TEST(DebugViewTable, NamesAndLookup) {
    const std::vector<std::string> expected = {"shaded",  "visibility",  "silhouettes", "wedges",
                                               "stencil", "group-parts", "error"};
    ASSERT_EQ(gpu::debugViews().size(), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const gpu::DebugViewInfo& v = gpu::debugViews()[i];
        EXPECT_EQ(v.name, expected[i]);
        EXPECT_EQ(static_cast<std::size_t>(v.view), i); // DebugView order
        EXPECT_FALSE(v.help.empty());
        EXPECT_EQ(&gpu::findDebugView(v.name), &v);
    }
    try {
        gpu::findDebugView("nope");
        FAIL() << "no InputError for an unknown view";
    } catch (const geometry::InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("'nope'"), std::string::npos) << message;
        for (const std::string& name : expected)
            EXPECT_NE(message.find(name), std::string::npos) << message;
    }
}

// Every view with every real-time method, on the three plates and a game level: no GL error
// (the renderer checks after the view, the fixture after the test), a note for every view but
// Shaded, and the views that replace the picture change it.
TEST_F(DebugViews, EveryViewRendersWithEveryMethod) {
    const geometry::Scene plates = geometry::loadScene(testutil::dataPath("plates-three.json"));
    const geometry::Scene level = geometry::loadScene(testutil::sharedPath("levels/oa_dm4.glb"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    for (const auto* scene : {&plates, &level}) {
        gpu::Renderer renderer(*scene, shaders);
        int errorFrames = 0; // the reference goes on across methods (same view and light)
        for (const char* method : {"hard", "wedges-additive", "wedges-multiply", "wedges-blend",
                                   "occlusion", "pcss", "auto"}) {
            const gpu::RenderSettings s = settings(method, 64);
            ++errorFrames;
            const Frame shaded = renderView(renderer, s, gpu::DebugView::Shaded);
            EXPECT_TRUE(shaded.stats.debugNote.empty());
            for (const gpu::DebugViewInfo& v : gpu::debugViews()) {
                SCOPED_TRACE(std::string(method) + " " + std::string(v.name));
                Frame f;
                ASSERT_NO_THROW(f = renderView(renderer, s, v.view));
                EXPECT_EQ(f.image.size(), std::size_t(64 * 64 * 4));
                if (v.view == gpu::DebugView::Shaded) continue;
                EXPECT_FALSE(f.stats.debugNote.empty());
                // The wedge methods draw their hulls (not the "not served" note).
                if (v.view == gpu::DebugView::WedgeWireframe &&
                    std::string_view(method).rfind("wedges-", 0) == 0) {
                    EXPECT_EQ(f.stats.debugNote.rfind("wedges: ", 0), 0u) << f.stats.debugNote;
                    EXPECT_EQ(f.stats.debugNote.find("method '"), std::string::npos)
                        << f.stats.debugNote;
                }
                EXPECT_EQ(f.stats.referenceSamplesDone,
                          v.view == gpu::DebugView::ErrorHeatMap
                              ? std::min(16 * errorFrames, s.samples)
                              : 0);
                if (v.view == gpu::DebugView::Visibility || v.view == gpu::DebugView::StencilCount ||
                    v.view == gpu::DebugView::ErrorHeatMap) {
                    EXPECT_GT(differingPixels(f.image, shaded.image), 64u * 64u / 4);
                }
            }
        }
    }
}

// The visibility view holds round(255 V) in every channel where there is a surface, dark blue
// where there is none. On a tie (255 V = n + 1/2, common with wedges-blend, whose V is a mean of
// 8-bit parts) the GL may round either way; nowhere else.
TEST_F(DebugViews, VisibilityViewIsVAsBytes) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    for (const char* method : {"hard", "wedges-blend", "pcss"}) {
        const Frame f = renderView(renderer, settings(method, 96), gpu::DebugView::Visibility);
        std::size_t ties = 0, wrong = 0, surface = 0, penumbra = 0;
        for (std::size_t i = 0; i < f.visibility.data.size(); ++i) {
            const std::uint8_t* p = &f.image[4 * i];
            const float v = f.visibility.data[i];
            if (std::isnan(v)) {
                wrong += p[0] != kNoSurface[0] || p[1] != kNoSurface[1] || p[2] != kNoSurface[2];
                continue;
            }
            ++surface;
            penumbra += v > 0.05f && v < 0.95f;
            const float scaled = 255.0f * v;
            const bool tie = std::abs(scaled - std::floor(scaled) - 0.5f) < 1e-3f;
            ties += tie;
            for (int c = 0; c < 3; ++c) {
                const int byte = p[c];
                wrong += tie ? byte != int(std::floor(scaled)) && byte != int(std::ceil(scaled))
                             : byte != int(std::lround(scaled));
            }
            wrong += p[3] != 255;
        }
        std::printf("%s: %zu surface pixels, %zu in the penumbra, %zu ties\n", method, surface,
                    penumbra, ties);
        EXPECT_GT(surface, 8000u) << method;
        if (std::string(method) != "hard") {
            EXPECT_GT(penumbra, 500u) << method; // grey levels, not only 0 and 1
        }
        EXPECT_EQ(wrong, 0u) << method;
    }
}

// Lines over the shaded image: some pixels change, most do not, and the lines are there in
// their colour. With `hard` (no wedges) the wedges view says so and is the shaded image.
TEST_F(DebugViews, LineViewsDrawOverTheShadedImage) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    const int size = 128;
    const gpu::RenderSettings s = settings("wedges-blend", size);
    const Frame shaded = renderView(renderer, s, gpu::DebugView::Shaded);
    const Frame edges = renderView(renderer, s, gpu::DebugView::SilhouetteEdges);
    const Frame wedges = renderView(renderer, s, gpu::DebugView::WedgeWireframe);
    GLint polygonMode[2] = {0, 0}; // the wireframe's line mode must not outlive the frame
    glGetIntegerv(GL_POLYGON_MODE, polygonMode);
    EXPECT_EQ(polygonMode[0], GL_FILL);
    writeImage("debug-silhouettes", edges.image, size, size);
    writeImage("debug-wedges", wedges.image, size, size);
    const std::size_t pixels = std::size_t(size) * size;
    // The plates' outlines in view: two plates of about 25 pixels a side (and the floor's
    // outline, out of view, hidden under it).
    const std::size_t edgePixels = differingPixels(edges.image, shaded.image);
    std::printf("silhouettes: %zu of %zu pixels changed\n", edgePixels, pixels);
    EXPECT_GT(edgePixels, 150u);
    EXPECT_LT(edgePixels, pixels / 20);
    std::size_t yellow = 0; // visible edges in full colour (kEdgeColour)
    for (std::size_t i = 0; i < pixels; ++i)
        yellow += edges.image[4 * i] == 255 && std::abs(edges.image[4 * i + 1] - 230) <= 1 &&
                  std::abs(edges.image[4 * i + 2] - 26) <= 1;
    EXPECT_GT(yellow, 100u);
    // Hull edges run on to infinity: many lines, yet far from everything.
    const std::size_t wedgePixels = differingPixels(wedges.image, shaded.image);
    std::printf("wedges: %zu of %zu pixels changed\n", wedgePixels, pixels);
    EXPECT_GT(wedgePixels, pixels / 50);
    EXPECT_LT(wedgePixels, pixels / 2);
    EXPECT_NE(wedges.stats.debugNote.find("16 wedge hulls"), std::string::npos)
        << wedges.stats.debugNote;

    const gpu::RenderSettings hard = settings("hard", size);
    const Frame hardShaded = renderView(renderer, hard, gpu::DebugView::Shaded);
    const Frame hardWedges = renderView(renderer, hard, gpu::DebugView::WedgeWireframe);
    EXPECT_EQ(hardWedges.stats.debugNote,
              "wedges: method 'hard' draws no wedges; showing the shaded image");
    EXPECT_EQ(differingPixels(hardWedges.image, hardShaded.image), 0u);
    const Frame hardParts = renderView(renderer, hard, gpu::DebugView::GroupParts);
    EXPECT_NE(hardParts.stats.debugNote.find("wedges-blend"), std::string::npos)
        << hardParts.stats.debugNote;
    EXPECT_EQ(differingPixels(hardParts.image, hardShaded.image), 0u);
    // The silhouettes do not depend on the method.
    const Frame hardEdges = renderView(renderer, hard, gpu::DebugView::SilhouetteEdges);
    EXPECT_EQ(differingPixels(hardEdges.image, hardShaded.image), edgePixels);
}

// The class of the stencil view's colour ramp a pixel shows (debug-stencil.frag: count 0 grey,
// 1 blue, 2 green, 3+ red, each times the headlight term 0.45 + 0.55 max(n . e, 0), e towards
// the eye), or -1 when it is none of them (within a byte or two of float rounding).
int stencilClass(const std::uint8_t* p, const glm::vec3& n, const glm::vec3& toEye) {
    static constexpr float kRamp[4][3] = {
        {0.90f, 0.90f, 0.90f}, {0.25f, 0.55f, 1.00f}, {0.20f, 0.85f, 0.25f}, {1.00f, 0.20f, 0.12f}};
    const float light = 0.45f + 0.55f * std::max(glm::dot(n, glm::normalize(toEye)), 0.0f);
    for (int k = 0; k < 4; ++k) {
        bool match = true;
        for (int c = 0; c < 3; ++c)
            match = match && std::abs(int(p[c]) - int(std::lround(255.0f * kRamp[k][c] * light))) <= 2;
        if (match) return k;
    }
    return -1;
}

// The count view against `hard`'s V of the same frame (the same volumes): V = 1 exactly where
// the count is zero. Overlapping plate shadows give counts of 2.
TEST_F(DebugViews, StencilCountMatchesHardVisibility) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    const Frame f = renderView(renderer, settings("hard", 128), gpu::DebugView::StencilCount);
    const geometry::FloatImage position = renderer.position(), normal = renderer.normal();
    writeImage("debug-stencil", f.image, 128, 128);
    std::size_t lit = 0, shadowed = 0, wrong = 0, two = 0;
    for (std::size_t i = 0; i < f.visibility.data.size(); ++i) {
        const float v = f.visibility.data[i];
        const std::uint8_t* p = &f.image[4 * i];
        if (std::isnan(v)) {
            wrong += p[0] != kNoSurface[0] || p[1] != kNoSurface[1] || p[2] != kNoSurface[2];
            continue;
        }
        const glm::vec3 n(normal.data[3 * i], normal.data[3 * i + 1], normal.data[3 * i + 2]);
        const int c = stencilClass(p, n, scene.camera.eye - testutil::pixelPosition(position, i));
        if (v == 1.0f) {
            ++lit;
            wrong += c != 0;
        } else {
            ++shadowed;
            wrong += c < 1;
            two += c == 2;
        }
    }
    EXPECT_GT(lit, 5000u);
    EXPECT_GT(shadowed, 1000u);
    EXPECT_GT(two, 100u);
    EXPECT_EQ(wrong, 0u);
}

// The error view's reference gains 16 samples a frame and, complete, is the `reference`
// method's V for the same N and seed (the same passes in the same order: equal to float
// rounding of nothing); the view is errorHeatMap's colours of |V - V_ref|. It stops once
// complete, survives a change of method, and restarts when the light moves.
TEST_F(DebugViews, ErrorViewAccumulatesTheReference) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    const int size = 64, samples = 64;
    gpu::RenderSettings s = settings("wedges-blend", size);
    s.samples = samples;
    s.seed = 7;
    s.errorScale = 0.05f; // wedges-blend's error is small: a scale that shows it

    gpu::Renderer reference(scene, shaders);
    gpu::RenderSettings r = s;
    r.method = "reference";
    reference.renderFrame(r);
    const geometry::FloatImage expected = reference.visibility();

    gpu::Renderer renderer(scene, shaders);
    EXPECT_EQ(renderer.referenceVisibility().width, 0);
    Frame f;
    for (int frame = 1; frame <= samples / 16; ++frame) {
        f = renderView(renderer, s, gpu::DebugView::ErrorHeatMap);
        EXPECT_EQ(f.stats.referenceSamplesDone, 16 * frame);
    }
    EXPECT_NE(f.stats.debugNote.find("reference 64/64 samples (complete)"), std::string::npos)
        << f.stats.debugNote;
    const geometry::FloatImage progressive = renderer.referenceVisibility();
    ASSERT_EQ(progressive.data.size(), expected.data.size());
    std::size_t differing = 0, surface = 0;
    double maxDiff = 0.0;
    for (std::size_t i = 0; i < expected.data.size(); ++i) {
        const float a = progressive.data[i], b = expected.data[i];
        if (std::isnan(a) || std::isnan(b)) {
            differing += std::isnan(a) != std::isnan(b);
            continue;
        }
        ++surface;
        maxDiff = std::max(maxDiff, double(std::abs(a - b)));
        differing += std::abs(a - b) > 1e-6f;
    }
    EXPECT_GT(surface, 2000u);
    EXPECT_LE(maxDiff, 1e-6);
    EXPECT_EQ(differing, 0u);

    // The view: errorHeatMap's colours of the method's V against that reference (its legend
    // strip below is not part of the view). Byte rounding ties may differ by one.
    const geometry::RgbImage heat = geometry::errorHeatMap(f.visibility.data, expected.data, size,
                                                           size, s.errorScale);
    std::size_t offByOne = 0, wrong = 0, hot = 0;
    for (std::size_t i = 0; i < std::size_t(size) * size; ++i) {
        int worst = 0;
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(int(f.image[4 * i + c]) - int(heat.rgb[3 * i + c])));
        offByOne += worst == 1;
        wrong += worst > 1;
        hot += heat.rgb[3 * i] > 40; // visibly non-black
    }
    writeImage("debug-error", f.image, size, size);
    EXPECT_EQ(wrong, 0u);
    EXPECT_LE(offByOne, std::size_t(size) * size / 100);
    EXPECT_GT(hot, 10u); // the comparison sees some error, not only black

    // Complete: no more samples. Another method keeps the reference.
    f = renderView(renderer, s, gpu::DebugView::ErrorHeatMap);
    EXPECT_EQ(f.stats.referenceSamplesDone, samples);
    gpu::RenderSettings hard = s;
    hard.method = "hard";
    f = renderView(renderer, hard, gpu::DebugView::ErrorHeatMap);
    EXPECT_EQ(f.stats.referenceSamplesDone, samples);
    // Moving the light restarts it.
    geometry::RectLight moved = scene.light;
    moved.center.x += 0.2f;
    hard.light = moved;
    f = renderView(renderer, hard, gpu::DebugView::ErrorHeatMap);
    EXPECT_EQ(f.stats.referenceSamplesDone, 16);
    EXPECT_NE(f.stats.debugNote.find("reference 16/64 samples,"), std::string::npos)
        << f.stats.debugNote;
}

// Group parts: which group is shown (wrapped both ways), and for the square over the floor the
// tiles' mean is wedges-blend's V: with one group that shadows, the blend of its parts into the
// empty state is those parts (stored at 8 bits).
TEST_F(DebugViews, GroupPartsShowsOneGroupsParts) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("parallel-square.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    const int size = 128, half = size / 2;
    gpu::RenderSettings s = settings("wedges-blend", size);
    int occluderGroup = -1;
    for (int g : {0, 1}) {
        s.debugGroup = g;
        const Frame f = renderView(renderer, s, gpu::DebugView::GroupParts);
        EXPECT_NE(f.stats.debugNote.find("group " + std::to_string(g) + " of 2"),
                  std::string::npos)
            << f.stats.debugNote;
        if (f.stats.debugNote.find("'occluder'") != std::string::npos) occluderGroup = g;
    }
    ASSERT_GE(occluderGroup, 0);
    s.debugGroup = occluderGroup - 2; // wraps to the same group
    const Frame f = renderView(renderer, s, gpu::DebugView::GroupParts);
    EXPECT_NE(f.stats.debugNote.find("group " + std::to_string(occluderGroup) + " of 2"),
              std::string::npos)
        << f.stats.debugNote;
    writeImage("debug-group-parts", f.image, size, size);

    // Tile k (2x2, part 0 top left) at tile pixel (tx, ty) shows source pixel (2 tx + 1,
    // 2 ty + 1) counted from the tile's lower left (debug-mosaic.frag); its first row and
    // column (from the lower left) are the line between tiles.
    std::size_t compared = 0, wrong = 0, shadow = 0;
    for (int ty = 1; ty < half; ++ty)
        for (int tx = 1; tx < half; ++tx) {
            const int sx = 2 * tx + 1, sy = 2 * ty + 1; // GL rows, bottom up
            const std::size_t src = std::size_t(size - 1 - sy) * size + sx;
            const float v = f.visibility.data[src];
            if (std::isnan(v)) continue;
            float mean = 0.0f;
            for (int k = 0; k < 4; ++k) {
                const int col = k % 2, rowFromTop = k / 2;
                const int gx = col * half + tx, gy = (1 - rowFromTop) * half + ty; // GL
                mean += f.image[4 * (std::size_t(size - 1 - gy) * size + gx)] / 255.0f / 4.0f;
            }
            ++compared;
            shadow += v < 0.95f;
            // 8-bit parts in the method, 8-bit tiles here: half a step each, and the wedges'
            // conservative coverage is the same arithmetic.
            wrong += std::abs(mean - v) > 2.0f / 255.0f;
        }
    EXPECT_GT(compared, 3000u);
    EXPECT_GT(shadow, 300u);
    EXPECT_LE(wrong, compared / 200);
}

// blitImage copies the frame's image (here, its visibility view) into another framebuffer at a
// viewport; at 1:1 the linear filter samples texel centres: an exact copy.
TEST_F(DebugViews, BlitImageCopiesTheView) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    const Frame f = renderView(renderer, settings("hard", 48), gpu::DebugView::Visibility);
    gpu::Texture target({.width = 64, .height = 64, .format = GL_RGBA8, .label = "blit-target"});
    gpu::Framebuffer fbo({.attachments = {{GL_COLOR_ATTACHMENT0, &target}}, .label = "blit"});
    const float clear[4] = {1.0f, 0.0f, 1.0f, 1.0f};
    glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, clear);
    glEnable(GL_SCISSOR_TEST); // the caller's state: the blit must not be clipped by it
    glScissor(0, 0, 1, 1);
    renderer.blitImage(5, 7, 48, 48, fbo.id());
    EXPECT_TRUE(glIsEnabled(GL_SCISSOR_TEST));
    glDisable(GL_SCISSOR_TEST);
    std::vector<std::byte> raw;
    target.read(GL_RGBA, GL_UNSIGNED_BYTE, raw); // bottom row first
    std::size_t wrong = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const std::uint8_t* p = reinterpret_cast<const std::uint8_t*>(&raw[4 * (y * 64 + x)]);
            const bool inside = x >= 5 && x < 53 && y >= 7 && y < 55;
            for (int c = 0; c < 4; ++c) {
                const std::uint8_t expected =
                    inside ? f.image[4 * (std::size_t(47 - (y - 7)) * 48 + (x - 5)) + c]
                           : std::uint8_t(c == 1 ? 0 : 255);
                wrong += p[c] != expected;
            }
        }
    EXPECT_EQ(wrong, 0u);
}

} // namespace
