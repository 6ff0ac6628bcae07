// The occlusion-texture method (gpu/src/methods/OcclusionMethod.cpp) on the GL driver:
// - a square occluder parallel to a square light against the closed form, with the defaults and
//   per prefilter (N-buffers, SAT, mipmaps: V in [0, 1], errors in the order measured);
// - an alpha-masked leaf card whose texture has a hole lights the ground beneath the hole (and
//   the G-buffer sees through it); methods without alpha masks give the card to occlusion;
// - a closed sphere: its far side dark, its lit cap not shadowed by its own slices, and no slice
//   seams (neighbouring pixels of the floor and of the sphere differ no more than the
//   reference's do);
// - parameter errors are InputErrors naming what is allowed.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"

#include <geometry/reference/Analytic.h>
#include <geometry/core/Error.h>
#include <geometry/reference/ErrorStats.h>
#include <geometry/shadow/OcclusionSlices.h>
#include <geometry/scene/Primitives.h>
#include <gpu/Methods.h>
#include <geometry/reference/Framing.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace {

using testutil::Rendered;

Rendered renderOcclusion(const geometry::Scene& scene, int size,
                         std::vector<gpu::ParameterValue> parameters = {}) {
    gpu::RenderSettings s = testutil::frameSettings("occlusion", size, size);
    s.parameters = std::move(parameters);
    return testutil::render(scene, s);
}

struct ClosedFormCheck {
    geometry::ErrorStats error;
    std::size_t outOfRange = 0; // V not finite or outside [0, 1]
    std::vector<float> exact;   // per pixel, NaN where no surface
};

// V of every surface pixel against visibilityParallelRects with `occluders` (every pixel of
// these scenes lies below the occluders it can see, or on top of one: V = 1 there).
// writeImages("name") after a failed expectation writes actual / expected / diff.
ClosedFormCheck againstClosedForm(const geometry::Scene& scene,
                                  std::span<const geometry::HorizontalRect> occluders,
                                  const Rendered& r) {
    std::vector<float> exact(r.visibility.data.size(), std::nanf(""));
    ClosedFormCheck c;
    for (std::size_t i = 0; i < exact.size(); ++i) {
        const float v = r.visibility.data[i];
        if (!std::isfinite(r.position.data[3 * i])) continue;
        if (!std::isfinite(v) || v < 0.0f || v > 1.0f) ++c.outOfRange;
        const glm::vec3 p = testutil::pixelPosition(r.position, i);
        std::vector<geometry::HorizontalRect> above;
        for (const auto& o : occluders)
            if (o.y > p.y + 1e-3f) above.push_back(o);
        exact[i] = geometry::visibilityParallelRects(scene.light, above, p);
    }
    c.error = geometry::compareVisibility(r.visibility.data, exact);
    c.exact = std::move(exact);
    return c;
}

class OcclusionMethod : public GlTest {};

// The occluder of data/parallel-square.json: 1 m square at y = 1.
const geometry::HorizontalRect kSquare{-0.5f, 0.5f, -0.5f, 0.5f, 1.0f};

void writeImagesOnFailure(const std::string& name, const Rendered& r, const ClosedFormCheck& c) {
    if (::testing::Test::HasFailure())
        testutil::writeComparisonImages("occlusion-" + name, r.visibility, c.exact);
}

// A lamp hung in a room (the viewer's lamp at spawn views): most walls, the floor's far parts
// and the ceiling lie beyond the slicing frustum (capped at 16 light sizes) or behind the
// light's plane, where the slices hold nothing. The paper's lookup calls them lit
// (outside=lit: 0.61 mean on oa_dm1's third spawn view at 320x180, against hard's 0.0038);
// outside=pcss (the default) shadows them from pcss's maps, counts them, and keeps within 0.01
// of hard's mean against raytrace. Measured at 128x72, N = 256: see the printout.
TEST_F(OcclusionMethod, LampInARoomShadowsWhatTheSlicesCannotHold) {
    for (const auto& [level, camera] :
         {std::pair{"oa_dm1.glb", 2}, std::pair{"kaos2.glb", 2}, std::pair{"kaos2.glb", 11}}) {
        SCOPED_TRACE(level);
        const geometry::Scene scene = testutil::levelWithLamp(level, camera);
        const Rendered r = testutil::render(scene, "occlusion", 128, 72, 1);
        const Rendered lit = testutil::render(scene, "occlusion", 128, 72, 1, {{"outside", "lit"}});
        const Rendered hard = testutil::render(scene, "hard", 128, 72, 1);
        const Rendered ref = testutil::render(scene, "raytrace", 128, 72, 256);
        const auto e = geometry::compareVisibility(r.visibility.data, ref.visibility.data);
        const auto el = geometry::compareVisibility(lit.visibility.data, ref.visibility.data);
        const auto eh = geometry::compareVisibility(hard.visibility.data, ref.visibility.data);
        const double outside = testutil::counter(r.stats, "occlusion_pixels_outside");
        std::printf("  %s camera %d 128x72 vs raytrace N=256: occlusion mean %.4f (%.2f%% > "
                    "0.05; %.0f of %zu pixels from pcss's maps), outside=lit %.4f, hard %.4f\n",
                    level, camera, e.meanAbs, e.badPixelPct, outside, e.pixels, el.meanAbs,
                    eh.meanAbs);
        EXPECT_GT(outside, 0.0);
        EXPECT_GE(testutil::counter(r.stats, "occlusion_outside_maps"), 1.0);
        EXPECT_LE(e.meanAbs, eh.meanAbs + 0.01);
        EXPECT_LE(e.badPixelPct, eh.badPixelPct + 2.0);
        EXPECT_GT(el.meanAbs, e.meanAbs + 0.05); // the paper's lookup: lit where it cannot see
    }
    // A scene the frustum holds whole draws no pcss maps.
    const geometry::Scene plate = geometry::loadScene(testutil::dataPath("parallel-square.json"));
    const Rendered p = testutil::render(plate, "occlusion", 64, 1);
    EXPECT_EQ(testutil::counter(p.stats, "occlusion_pixels_outside"), 0.0);
    EXPECT_EQ(testutil::counter(p.stats, "occlusion_outside_maps"), 0.0);
}

TEST_F(OcclusionMethod, ParallelSquareMatchesTheClosedForm) {
    const auto scene = geometry::loadScene(testutil::dataPath("parallel-square.json"));
    const Rendered r = renderOcclusion(scene, 128);
    const ClosedFormCheck c = againstClosedForm(scene, {&kSquare, 1}, r);
    std::printf("  defaults (8 slices, nbuffers, leak fix near slice planes): mean %.4f, "
                "p99 %.4f, max %.4f, %.2f%% > 0.05\n",
                c.error.meanAbs, c.error.p99, c.error.max, c.error.badPixelPct);
    EXPECT_EQ(c.outOfRange, 0u);
    EXPECT_LE(c.error.meanAbs, 0.03); // the bound
    // What remains (measured mean 0.0030, 1.64% of the pixels off by more than 0.05, p99 0.06):
    // the plate looked up at its slab's middle plane, 1/16 of the casters' depth range below
    // it, and the N-buffers' interpolation between window sizes.
    EXPECT_LE(c.error.meanAbs, 0.005);
    EXPECT_LE(c.error.badPixelPct, 2.5);
    writeImagesOnFailure("parallel-square", r, c);

    // The paper's leak fix writes the plate into the next slab too: its penumbra counts twice,
    // V = (1 - I)(1 - I'), darker than 1 - I ("umbrae are a little overestimated", §3.4).
    const Rendered paper = renderOcclusion(scene, 128, {{"leakfix", "paper"}});
    const ClosedFormCheck d = againstClosedForm(scene, {&kSquare, 1}, paper);
    std::printf("  leakfix=paper: mean %.4f, p99 %.4f, max %.4f, %.2f%% > 0.05\n",
                d.error.meanAbs, d.error.p99, d.error.max, d.error.badPixelPct);
    EXPECT_GT(d.error.meanAbs, 2.0 * c.error.meanAbs); // measured 0.0102
    EXPECT_LE(d.error.meanAbs, 0.03);
}

// Slices, prefilter and shadow maps depend on the light and the casters only: a second frame
// with the same light reuses them (counted) and gives the same V bit for bit; a moved light
// redraws them, and V equals a fresh renderer's at that light (nothing stale). The demo's walls
// reach past the slicing frustum, so occlusion's pcss fallback runs too.
TEST_F(OcclusionMethod, AStillLightReusesTheSlicesAndMaps) {
    const auto scene = geometry::loadScene(testutil::dataPath("demo.json"));
    const auto same = [](const geometry::FloatImage& a, const geometry::FloatImage& b) {
        if (a.data.size() != b.data.size()) return false;
        for (std::size_t i = 0; i < a.data.size(); ++i)
            if (!(a.data[i] == b.data[i] || (std::isnan(a.data[i]) && std::isnan(b.data[i]))))
                return false;
        return true;
    };
    geometry::RectLight moved = scene.light;
    moved.center += 0.3f * glm::normalize(moved.u);
    struct Case {
        std::string method;
        std::vector<std::string> cachedCounters;
    };
    for (const Case& c : {Case{"occlusion", {"occlusion_slices_cached",
                                             "occlusion_outside_maps_cached"}},
                          Case{"pcss", {"pcss_maps_cached"}},
                          Case{"sample-maps", {"sample_maps_cached"}}}) {
        SCOPED_TRACE(c.method);
        testutil::SceneRenderer sr(scene);
        gpu::RenderSettings s = testutil::frameSettings(c.method, 64, 64);
        const gpu::FrameStats first = sr.renderer.renderFrame(s);
        const geometry::FloatImage v1 = sr.renderer.visibility();
        const gpu::FrameStats second = sr.renderer.renderFrame(s);
        const geometry::FloatImage v2 = sr.renderer.visibility();
        s.light = moved;
        const gpu::FrameStats third = sr.renderer.renderFrame(s);
        const geometry::FloatImage v3 = sr.renderer.visibility();
        for (const std::string& name : c.cachedCounters) {
            SCOPED_TRACE(name);
            EXPECT_EQ(testutil::counter(first, name), 0.0);
            EXPECT_EQ(testutil::counter(second, name), 1.0);
            EXPECT_EQ(testutil::counter(third, name), 0.0);
        }
        if (c.method == "occlusion") {
            EXPECT_GT(testutil::counter(first, "occlusion_pixels_outside"), 0.0);
        }
        EXPECT_TRUE(same(v1, v2));
        EXPECT_FALSE(same(v1, v3));
        testutil::SceneRenderer fresh(scene);
        fresh.renderer.renderFrame(s);
        EXPECT_TRUE(same(v3, fresh.renderer.visibility()));
    }
}

TEST_F(OcclusionMethod, LeakFixClosesTheGapsOfATiltedSheet) {
    // A plate tilted 30° crosses the slab planes: without the fix, light slips between the
    // pieces looked up half a slab higher and lower (stripes across its shadow).
    const auto scene = geometry::loadScene(testutil::dataPath("plate-tilted.json"));
    const Rendered ref = testutil::render(scene, "reference", 128, 256);
    double mean[3];
    const char* modes[3] = {"off", "on", "paper"};
    for (int m = 0; m < 3; ++m) {
        const Rendered r = renderOcclusion(scene, 128, {{"leakfix", modes[m]}});
        const auto e = geometry::compareVisibility(r.visibility.data, ref.visibility.data);
        std::printf("  plate-tilted leakfix=%-5s vs reference N=256: mean %.4f, p99 %.4f, "
                    "%.2f%% > 0.05\n",
                    modes[m], e.meanAbs, e.p99, e.badPixelPct);
        mean[m] = e.meanAbs;
    }
    // Measured 0.0178 (off), 0.0134 (near the planes), 0.0256 (the paper's: every fragment).
    EXPECT_LT(mean[1], 0.85 * mean[0]);
    EXPECT_LT(mean[1], 0.7 * mean[2]);
}

TEST_F(OcclusionMethod, PrefiltersErrInTheOrderMeasured) {
    const auto scene = geometry::loadScene(testutil::dataPath("parallel-square.json"));
    struct Result {
        const char* prefilter;
        ClosedFormCheck check;
    };
    std::vector<Result> results;
    for (const char* prefilter : {"sat", "nbuffers", "mipmaps"}) {
        const Rendered r = renderOcclusion(scene, 128, {{"prefilter", prefilter}});
        const ClosedFormCheck c = againstClosedForm(scene, {&kSquare, 1}, r);
        std::printf("  %-9s mean %.4f, p99 %.4f, max %.4f, %.2f%% > 0.05\n", prefilter,
                    c.error.meanAbs, c.error.p99, c.error.max, c.error.badPixelPct);
        EXPECT_EQ(c.outOfRange, 0u) << prefilter;
        writeImagesOnFailure(std::string("parallel-square-") + prefilter, r, c);
        results.push_back({prefilter, c});
    }
    // Measured 0.0019 (SAT: the exact box), 0.0030 (N-buffers: exact for power-of-two windows,
    // interpolated between), 0.0057 (mipmaps: aligned dyadic blocks).
    EXPECT_LT(results[0].check.error.meanAbs, results[1].check.error.meanAbs);
    EXPECT_LT(results[1].check.error.meanAbs, results[2].check.error.meanAbs);
    EXPECT_LE(results[0].check.error.meanAbs, 0.003);
    EXPECT_LE(results[2].check.error.meanAbs, 0.008);
}

// A 2 × 2 m leaf card at y = 1 whose texture is opaque except a hole over its middle half
// (x, z in [-0.5, 0.5]), above a ground quad, under a 0.5 m square light at y = 3.
geometry::Scene leafCardScene(geometry::AlphaMode mode) {
    geometry::Scene scene;
    scene.camera = {.eye = {0.0f, 5.0f, 2.5f}, .target = {0.0f, 0.0f, 0.0f}, .fovYDeg = 50.0f};
    scene.light = {.center = {0.0f, 3.0f, 0.0f}, .u = {0.5f, 0.0f, 0.0f}, .v = {0.0f, 0.0f, 0.5f}};
    scene.objects.push_back({"ground", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 0, 0}, {3, 0, 0}, {0, 0, -3})});
    geometry::MeshData card = geometry::makeQuad({0, 1, 0}, {1, 0, 0}, {0, 0, 1});
    card.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    geometry::TextureImage texture;
    texture.width = texture.height = 32;
    texture.rgba8.resize(32 * 32 * 4);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            std::uint8_t* t = &texture.rgba8[(y * 32 + x) * 4];
            const bool hole = x >= 8 && x < 24 && y >= 8 && y < 24;
            t[0] = 60, t[1] = 140, t[2] = 40, t[3] = hole ? 0 : 255;
        }
    card.textures.push_back(std::move(texture));
    geometry::Material leaf;
    leaf.name = "leaf";
    leaf.alphaMode = mode;
    leaf.doubleSided = true;
    leaf.baseColorTexture = 0;
    card.materials.push_back(leaf);
    card.triangleMaterial.assign(card.triangles.size(), 0);
    scene.objects.push_back({"leaf card", geometry::ShadowMethod::Auto, std::move(card)});
    return scene;
}

// The card minus its hole, as four rectangles.
const geometry::HorizontalRect kCardFrame[] = {{-1.0f, -0.5f, -1.0f, 1.0f, 1.0f},
                                               {0.5f, 1.0f, -1.0f, 1.0f, 1.0f},
                                               {-0.5f, 0.5f, -1.0f, -0.5f, 1.0f},
                                               {-0.5f, 0.5f, 0.5f, 1.0f, 1.0f}};

TEST_F(OcclusionMethod, LeafCardLightsTheGroundBeneathItsHole) {
    const geometry::Scene scene = leafCardScene(geometry::AlphaMode::Mask);
    const Rendered r = renderOcclusion(scene, 128);
    const ClosedFormCheck c = againstClosedForm(scene, kCardFrame, r);
    std::size_t beneath = 0, beneathDark = 0, throughHole = 0, underLeaf = 0, underLeafLit = 0;
    for (std::size_t i = 0; i < r.visibility.data.size(); ++i) {
        if (!std::isfinite(r.visibility.data[i])) continue;
        const glm::vec3 p = testutil::pixelPosition(r.position, i);
        const float v = r.visibility.data[i];
        if (std::abs(p.y) > 1e-3f) continue; // ground only
        const float exact = geometry::visibilityParallelRects(scene.light, kCardFrame, p);
        // Seen through the hole: the ray from the camera to P crosses y = 1 inside it.
        const glm::vec3 e = scene.camera.eye;
        const glm::vec3 x = e + (p - e) * ((e.y - 1.0f) / (e.y - p.y));
        throughHole += std::abs(x.x) < 0.45f && std::abs(x.z) < 0.45f;
        if (exact == 1.0f && std::abs(p.x) < 0.5f && std::abs(p.z) < 0.5f) {
            ++beneath; // the whole light through the hole
            beneathDark += v < 0.9f;
        }
        if (exact == 0.0f) {
            ++underLeaf;
            underLeafLit += v > 0.1f;
        }
    }
    std::printf("  leaf card: mean %.4f, p99 %.4f, %.2f%% > 0.05; %zu ground pixels lit through "
                "the hole (%zu below 0.9), %zu in the card's umbra (%zu above 0.1), %zu seen "
                "through the hole\n",
                c.error.meanAbs, c.error.p99, c.error.badPixelPct, beneath, beneathDark,
                underLeaf, underLeafLit, throughHole);
    EXPECT_EQ(c.outOfRange, 0u);
    EXPECT_GT(beneath, 100u);
    EXPECT_EQ(beneathDark, 0u);
    EXPECT_GT(underLeaf, 100u);
    EXPECT_EQ(underLeafLit, 0u);
    EXPECT_GT(throughHole, 100u); // the G-buffer cut the hole out too
    EXPECT_LE(c.error.meanAbs, 0.03);
    writeImagesOnFailure("leaf-card", r, c);
}

TEST_F(OcclusionMethod, BlendedCardIsTestedAsMask) {
    // BLEND at alpha 0/1 texels: the same picture as MASK (and a warning on stderr).
    const Rendered mask = renderOcclusion(leafCardScene(geometry::AlphaMode::Mask), 64);
    const Rendered blend = renderOcclusion(leafCardScene(geometry::AlphaMode::Blend), 64);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < mask.visibility.data.size(); ++i) {
        const float a = mask.visibility.data[i], b = blend.visibility.data[i];
        differ += std::isfinite(a) != std::isfinite(b) || (std::isfinite(a) && a != b);
    }
    EXPECT_EQ(differ, 0u);
}

TEST_F(OcclusionMethod, MethodsWithoutAlphaMasksGiveTheCardToTheAlphaPath) {
    // A method that occludes with whole triangles does not refuse the card, nor shadow it as
    // opaque: it shadows the ground (which casts on nothing here) and auto's alpha path (sample
    // maps: the card lies in front of the light) the card, so V is that of sample-maps on the
    // card alone, and each object's
    // choice names its path and why.
    const geometry::Scene scene = leafCardScene(geometry::AlphaMode::Mask);
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::RenderSettings s;
    s.width = s.height = 48;
    s.method = "sample-maps";
    geometry::Scene cardOnly = scene;
    cardOnly.objects[0].method = geometry::ShadowMethod::None; // the ground receives only
    geometry::FloatImage alphaPath;
    {
        gpu::Renderer alone(cardOnly, shaders);
        alone.renderFrame(s);
        alphaPath = alone.visibility();
    }
    gpu::Renderer renderer(scene, shaders);
    for (const char* method : {"hard", "reference", "wedges-additive", "wedges-bitmask"}) {
        s.method = method;
        const gpu::FrameStats stats = renderer.renderFrame(s);
        const geometry::FloatImage v = renderer.visibility();
        double maxDiff = 0.0;
        std::size_t finite = 0;
        for (std::size_t i = 0; i < v.data.size(); ++i) {
            if (!std::isfinite(v.data[i])) continue;
            ++finite;
            maxDiff = std::max(maxDiff, double(std::abs(v.data[i] - alphaPath.data[i])));
        }
        EXPECT_GT(finite, 1000u) << method;
        EXPECT_LT(maxDiff, 1e-5) << method;
        ASSERT_EQ(stats.objectChoices.size(), 2u) << method;
        for (const auto& choice : stats.objectChoices) {
            if (scene.objects[choice.object].name == "leaf card") {
                EXPECT_EQ(choice.path, "sample-maps") << method;
                EXPECT_NE(choice.reason.find("leaf (MASK 0.50)"), std::string::npos)
                    << choice.reason;
                EXPECT_NE(choice.reason.find(method), std::string::npos) << choice.reason;
            } else {
                EXPECT_EQ(choice.path, method) << choice.reason;
            }
        }
    }
}

// Pairs of horizontally or vertically neighbouring pixels on one smooth surface.
struct Jumps {
    std::size_t pairs = 0;
    double max = 0.0;
    std::size_t over = 0; // differing by more than the threshold
};

Jumps neighbourJumps(const Rendered& r, int size, const std::function<bool(std::size_t)>& on,
                     double threshold) {
    Jumps j;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const std::size_t i = std::size_t(y) * size + x;
            if (!on(i)) continue;
            for (const std::size_t n : {i + 1, i + size}) {
                if ((n == i + 1 && x + 1 >= size) || (n == i + size && y + 1 >= size) || !on(n))
                    continue;
                const double d = std::abs(r.visibility.data[i] - r.visibility.data[n]);
                ++j.pairs;
                j.max = std::max(j.max, d);
                j.over += d > threshold;
            }
        }
    return j;
}

TEST_F(OcclusionMethod, ClosedSphereShadowsItselfWithoutSeams) {
    const auto scene = geometry::loadScene(testutil::dataPath("sphere.json"));
    const int size = 128;
    const Rendered r = renderOcclusion(scene, size);
    const Rendered ref = testutil::render(scene, "reference", size, 256);
    const glm::vec3 centre(0.0f, 1.0f, 0.0f); // data/sphere.json, radius 0.5
    auto onSphere = [&](std::size_t i) {
        return std::isfinite(r.visibility.data[i]) &&
               glm::length(testutil::pixelPosition(r.position, i) - centre) < 0.51f;
    };
    auto onFloor = [&](std::size_t i) {
        return std::isfinite(r.visibility.data[i]) &&
               std::abs(testutil::pixelPosition(r.position, i).y) < 1e-3f;
    };
    std::size_t farSide = 0, farLit = 0, cap = 0, capShadowed = 0;
    for (std::size_t i = 0; i < r.visibility.data.size(); ++i) {
        if (!onSphere(i)) continue;
        const glm::vec3 p = testutil::pixelPosition(r.position, i);
        const glm::vec3 n = testutil::pixelPosition(r.normal, i);
        const float front = geometry::horizonFraction(scene.light, p, n);
        if (front == 0.0f) {
            ++farSide;
            farLit += r.visibility.data[i] > 0.02f;
        } else if (front == 1.0f && ref.visibility.data[i] == 1.0f) {
            ++cap; // all of the light in front and, says the reference, nothing in the way
            capShadowed += r.visibility.data[i] < 0.93f;
        }
    }
    // Seams would be steps where the sphere or the floor crosses a slice plane: no pair of
    // neighbours on either may differ much more than the reference's do (its penumbrae are as
    // steep, plus sampling noise of 1/256).
    const Jumps floor = neighbourJumps(r, size, onFloor, 0.1);
    const Jumps floorRef = neighbourJumps(ref, size, onFloor, 0.1);
    const Jumps sphere = neighbourJumps(r, size, onSphere, 0.1);
    const Jumps sphereRef = neighbourJumps(ref, size, onSphere, 0.1);
    const auto e = geometry::compareVisibility(r.visibility.data, ref.visibility.data);
    std::printf("  sphere: far side %zu pixels (%zu with V > 0.02), lit cap %zu (%zu below "
                "0.93); neighbour jumps floor max %.3f (reference %.3f), > 0.1: %zu (reference "
                "%zu) of %zu pairs; sphere max %.3f (reference %.3f), > 0.1: %zu (reference "
                "%zu) of %zu; vs reference N=256: mean %.4f, p99 %.4f, %.2f%% > 0.05\n",
                farSide, farLit, cap, capShadowed, floor.max, floorRef.max, floor.over,
                floorRef.over, floor.pairs, sphere.max, sphereRef.max, sphere.over,
                sphereRef.over, sphere.pairs, e.meanAbs, e.p99, e.badPixelPct);
    EXPECT_GT(farSide, 150u);
    EXPECT_EQ(farLit, 0u);
    EXPECT_GT(cap, 150u);
    // Measured: 4 pixels at 0.95–0.97 near the cap's rim (the slab in front holds the cap's top,
    // looked up half a slab away from where it is).
    EXPECT_EQ(capShadowed, 0u);
    EXPECT_GT(floor.pairs, 10000u);
    EXPECT_LE(floor.max, floorRef.max + 0.02);
    EXPECT_LE(floor.over, floorRef.over); // measured 76 against 108
    EXPECT_LE(sphere.max, sphereRef.max + 0.02);
    EXPECT_LE(sphere.over, sphereRef.over); // measured 136 against 143
}

// A ceiling just over the light (between the light's plane and the slices' centre of
// projection, copDistance behind it) hides nothing in front of the light, yet the slicing
// projection rasterises it; clamped into the first slab it covered every receiver the frustum
// holds (textured oa_dm5's third spawn view with the lamp: 154 pixels drawn black that the
// light sees whole). The floor under a plate must match the reference.
TEST_F(OcclusionMethod, SurfacesBehindTheLightsPlaneHideNothing) {
    geometry::Scene scene;
    scene.camera = {.eye = {2.5f, 1.6f, 3.5f}, .target = {0.0f, 0.0f, 0.0f}, .fovYDeg = 50.0f};
    scene.light = {.center = {0.0f, 2.0f, 0.0f}, .u = {0.3f, 0.0f, 0.0f}, .v = {0.0f, 0.0f, 0.3f}};
    scene.objects.push_back({"floor", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 0, 0}, {1.5f, 0, 0}, {0, 0, -1.5f})});
    scene.objects.push_back({"plate", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0.2f, 0.8f, 0.0f}, {0.3f, 0, 0}, {0, 0, -0.3f})});
    scene.objects.push_back({"ceiling", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 2.05f, 0}, {3, 0, 0}, {0, 0, -3})});
    const std::vector<std::size_t> casters = {0, 1, 2};
    const geometry::OcclusionFrame f = geometry::fitOcclusionFrame(scene, casters, 8);
    ASSERT_GT(f.copDistance, 0.05f); // the ceiling lies between the light and the projection's centre
    const Rendered r = renderOcclusion(scene, 96);
    const Rendered ref = testutil::render(scene, "reference", 96, 256);
    std::size_t inside = 0, wrong = 0;
    const double outside = testutil::counter(r.stats, "occlusion_pixels_outside");
    for (std::size_t i = 0; i < r.visibility.data.size(); ++i) {
        const float v = r.visibility.data[i], t = ref.visibility.data[i];
        if (!std::isfinite(v) || !std::isfinite(t)) continue;
        ++inside;
        wrong += std::abs(v - t) > 0.25f;
    }
    const auto e = geometry::compareVisibility(r.visibility.data, ref.visibility.data);
    std::printf("  ceiling 0.05 over the light (copDistance %.2f): vs reference N=256 mean %.4f, "
                "%zu of %zu pixels off by > 0.25 (%.0f from pcss's maps)\n",
                f.copDistance, e.meanAbs, wrong, inside, outside);
    EXPECT_GT(inside - static_cast<std::size_t>(outside), 1500u); // the slices hold the floor
    // Measured: 0 (before the fix the floor inside the frustum was black: thousands).
    EXPECT_LE(wrong, 20u);
    EXPECT_LT(e.meanAbs, 0.02);
}

TEST_F(OcclusionMethod, RampCrossingEverySlicePlaneHasNoSeams) {
    // A ramp (22°) under a square plate crosses the slab planes where the plate's penumbra and
    // the ramp's own slices are looked up: V must stay as smooth along it as the reference's.
    geometry::Scene scene;
    scene.camera = {.eye = {3.0f, 4.5f, 4.0f}, .target = {0.0f, 0.8f, 0.0f}, .fovYDeg = 45.0f};
    scene.light = {.center = {0.0f, 3.0f, 0.0f}, .u = {0.5f, 0.0f, 0.0f}, .v = {0.0f, 0.0f, 0.5f}};
    scene.objects.push_back({"floor", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 0, 0}, {3, 0, 0}, {0, 0, -3})});
    scene.objects.push_back({"ramp", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 0.8f, 0}, {1.5f, 0, 0}, {0, 0.6f, 1.5f})});
    scene.objects.push_back({"plate", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0.3f, 2.0f, 0.2f}, {0.4f, 0, 0}, {0, 0, -0.4f})});
    const int size = 128;
    const Rendered r = renderOcclusion(scene, size);
    const Rendered ref = testutil::render(scene, "reference", size, 256);
    // On the ramp: the plane through (0, 0.8, 0) with normal (0, 1.5, -0.6).
    auto onRamp = [&](std::size_t i) {
        if (!std::isfinite(r.visibility.data[i])) return false;
        const glm::vec3 p = testutil::pixelPosition(r.position, i) - glm::vec3(0, 0.8f, 0);
        return std::abs(glm::dot(p, glm::normalize(glm::vec3(0, 1.5f, -0.6f)))) < 1e-3f;
    };
    // Neighbours on the ramp whose depths straddle a slab plane against those that do not: a
    // seam is a step where the lookup changes slabs.
    std::vector<std::size_t> casters = {0, 1, 2};
    const geometry::OcclusionFrame f = geometry::fitOcclusionFrame(scene, casters, 8);
    auto slab = [&](std::size_t i) {
        return std::floor((f.depth(testutil::pixelPosition(r.position, i)) - f.zNear) /
                          f.sliceDepth());
    };
    double straddling = 0.0, within = 0.0;
    std::size_t straddlingPairs = 0, pairs = 0;
    for (int y = 0; y + 1 < size; ++y)
        for (int x = 0; x + 1 < size; ++x) {
            const std::size_t i = std::size_t(y) * size + x;
            if (!onRamp(i)) continue;
            for (const std::size_t n : {i + 1, i + size}) {
                if (!onRamp(n)) continue;
                const double d = std::abs(r.visibility.data[i] - r.visibility.data[n]);
                ++pairs;
                if (slab(i) != slab(n)) {
                    ++straddlingPairs;
                    straddling = std::max(straddling, d);
                } else {
                    within = std::max(within, d);
                }
            }
        }
    const Jumps ramp = neighbourJumps(r, size, onRamp, 0.05);
    const Jumps rampRef = neighbourJumps(ref, size, onRamp, 0.05);
    const auto e = geometry::compareVisibility(r.visibility.data, ref.visibility.data);
    std::printf("  ramp: %zu neighbour pairs, %zu straddling a slab plane: largest jump %.3f "
                "across a plane, %.3f within a slab (reference %.3f); vs reference N=256: mean "
                "%.4f, p99 %.4f\n",
                pairs, straddlingPairs, straddling, within, rampRef.max, e.meanAbs, e.p99);
    EXPECT_GT(straddlingPairs, 200u);
    EXPECT_LE(straddling, within + 0.01);
    // Steeper than the reference's only where the plate is looked up half a slab below itself
    // (a narrower penumbra): measured 0.180 against 0.148.
    EXPECT_LE(ramp.max, rampRef.max + 0.05);
}

TEST_F(OcclusionMethod, ParameterErrorsNameWhatIsAllowed) {
    const gpu::MethodInfo& m = gpu::findMethod("occlusion");
    EXPECT_TRUE(m.alphaMasks);
    struct Case {
        gpu::ParameterValue given;
        const char* allowed;
    };
    for (const Case& c : {Case{{"slices", "5"}, "4, 8, 16"},
                          Case{{"prefilter", "box"}, "nbuffers, sat, mipmaps"},
                          Case{{"leakfix", "maybe"}, "auto, on, off"},
                          Case{{"resolution", "300"}, "256, 512, 1024"},
                          Case{{"horizon", "1"}, "on, off"},
                          Case{{"slice", "8"}, "slices, prefilter"}}) {
        try {
            const std::vector<gpu::ParameterValue> given = {c.given};
            gpu::resolveParameters(m, given);
            ADD_FAILURE() << c.given.name << "=" << c.given.value << " accepted";
        } catch (const geometry::InputError& e) {
            EXPECT_NE(std::string(e.what()).find(c.allowed), std::string::npos) << e.what();
        }
    }
    // Through the renderer as well: nothing is drawn.
    const auto scene = geometry::loadScene(testutil::dataPath("parallel-square.json"));
    EXPECT_THROW(renderOcclusion(scene, 32, {{"slices", "32"}}), geometry::InputError);
    // Every allowed combination of slices and prefilter renders, V in [0, 1].
    for (const char* slices : {"4", "16"})
        for (const char* prefilter : {"nbuffers", "sat", "mipmaps"}) {
            const Rendered r = renderOcclusion(
                scene, 32, {{"slices", slices}, {"prefilter", prefilter}, {"resolution", "256"}});
            for (const float v : r.visibility.data) {
                if (std::isfinite(v)) {
                    ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << slices << prefilter;
                }
            }
        }
}

} // namespace
