// Renderer: the frame of penumbra-render, in a fixed order.
// - G-buffer: world position, viewer-facing normal, albedo, shading normal, reversed-Z depth +
//   stencil (alpha-tested materials cut out);
// - silhouettes of the light centre (CPU), uploaded once for every method of the frame;
// - visibility: the method's object (gpu/src/methods/), chosen by name from gpu/Methods.h;
// - shade: albedo * (ambient + V * n.l).
#include <gpu/Renderer.h>

#include <geometry/core/Error.h>
#include <gpu/gl/State.h>

#include "engine/DebugViews.h"
#include "engine/Method.h"
#include "engine/ShaderBindings.h"
#include "engine/Targets.h"
#include "passes/GBufferPass.h"
#include "passes/ShadePass.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <numeric>

#include <unistd.h>

namespace gpu {

void FrameContext::addCpuTime(std::string_view stage, double ms) const {
    // Stages repeat per light sample in the reference: same name, summed.
    for (auto& t : stats.cpu)
        if (t.name == stage) {
            t.ms += ms;
            return;
        }
    stats.cpu.push_back({std::string(stage), ms});
}

void FrameContext::addCounter(std::string_view name, double value) const {
    for (auto& c : stats.counters)
        if (c.name == name) {
            c.value += value;
            return;
        }
    stats.counters.push_back({std::string(name), value});
}

namespace {

constexpr DebugViewInfo kDebugViews[] = {
    {DebugView::Shaded, "shaded", "the shaded image"},
    {DebugView::Visibility, "visibility", "V as grey (white lit, black umbra)"},
    {DebugView::SilhouetteEdges, "silhouettes",
     "the light centre's silhouette edges over the shaded image (dim where hidden)"},
    {DebugView::WedgeWireframe, "wedges",
     "the wedge hulls of the method's wedge pass as lines (wedge methods, auto)"},
    {DebugView::StencilCount, "stencil",
     "the light centre's z-fail shadow-volume count: grey 0, blue 1, green 2, red 3+"},
    {DebugView::GroupParts, "group-parts",
     "wedges-blend: one silhouette group's per-part visibility buffers as tiles (--debug-group)"},
    {DebugView::ErrorHeatMap, "error",
     "|V - V_ref| heat map against a reference accumulated over frames (16 samples a frame)"},
};

std::string debugViewNames() {
    std::string names;
    for (const DebugViewInfo& v : kDebugViews)
        names += (names.empty() ? "" : ", ") + std::string(v.name);
    return names;
}

} // namespace

std::span<const DebugViewInfo> debugViews() { return kDebugViews; }

const DebugViewInfo& findDebugView(std::string_view name) {
    for (const DebugViewInfo& v : kDebugViews)
        if (v.name == name) return v;
    throw geometry::InputError("unknown debug view '" + std::string(name) +
                               "' (known: " + debugViewNames() + ")");
}

const DebugViewInfo& debugViewInfo(DebugView view) {
    for (const DebugViewInfo& v : kDebugViews)
        if (v.view == view) return v;
    throw geometry::InputError("RenderSettings::debugView: not a DebugView (" +
                               std::to_string(static_cast<int>(view)) + ")");
}

namespace {

// Reversed-Z perspective with an infinite far plane, for glClipControl(LOWER_LEFT, ZERO_TO_ONE):
// depth = near / view distance, 1 at the near plane, 0 at infinity (where w = 0 points land).
glm::mat4 infiniteReversedZ(float fovYRad, float aspect, float zNear) {
    const float f = 1.0f / std::tan(0.5f * fovYRad);
    glm::mat4 p(0.0f);
    p[0][0] = f / aspect;
    p[1][1] = f;
    p[2][3] = -1.0f;
    p[3][2] = zNear;
    return p;
}

// "11.8 GiB", "0.9 MiB", "244.1 KiB".
std::string bytesText(double bytes) {
    const bool gib = bytes >= double(1ull << 30), mib = bytes >= double(1 << 20);
    const char* unit = gib ? "GiB" : mib ? "MiB" : "KiB";
    const double scale = gib ? double(1ull << 30) : mib ? double(1 << 20) : 1024.0;
    char text[32];
    std::snprintf(text, sizeof text, "%.1f %s", bytes / scale, unit);
    return text;
}

// What the GL implementation allows the frame's per-pixel targets, queried once.
struct SizeLimits {
    int maxWidth = 0, maxHeight = 0;
    std::string sides;         // the GL limits behind maxWidth and maxHeight, for messages
    std::size_t memory = 0;    // bytes the per-pixel targets may take
    std::string memorySource;  // where `memory` comes from, for messages
};

SizeLimits querySizeLimits() {
    GLint texture = 0, renderbuffer = 0, fbWidth = 0, fbHeight = 0, viewport[2] = {};
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &texture);
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbuffer);
    glGetIntegerv(GL_MAX_FRAMEBUFFER_WIDTH, &fbWidth);
    glGetIntegerv(GL_MAX_FRAMEBUFFER_HEIGHT, &fbHeight);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport);
    SizeLimits l;
    l.maxWidth = std::min({texture, renderbuffer, fbWidth, viewport[0]});
    l.maxHeight = std::min({texture, renderbuffer, fbHeight, viewport[1]});
    l.sides = "GL_MAX_TEXTURE_SIZE " + std::to_string(texture) + ", GL_MAX_RENDERBUFFER_SIZE " +
              std::to_string(renderbuffer) + ", GL_MAX_FRAMEBUFFER_WIDTH/HEIGHT " +
              std::to_string(fbWidth) + "/" + std::to_string(fbHeight) +
              ", GL_MAX_VIEWPORT_DIMS " + std::to_string(viewport[0]) + "x" +
              std::to_string(viewport[1]);
    // Core GL cannot say how much memory there is: the vendor queries where present (3/4 of it,
    // leaving room for the scene's buffers), else half of main memory, which is where a software
    // renderer (llvmpipe) keeps its textures.
    if (epoxy_has_gl_extension("GL_NVX_gpu_memory_info")) {
        GLint kib = 0;
        glGetIntegerv(GL_GPU_MEMORY_INFO_DEDICATED_VIDMEM_NVX, &kib);
        if (kib > 0) {
            l.memory = std::size_t(kib) * 1024 / 4 * 3;
            l.memorySource = "3/4 of the GPU's " + bytesText(double(kib) * 1024.0) +
                             " of dedicated memory";
        }
    } else if (epoxy_has_gl_extension("GL_ATI_meminfo")) {
        GLint free[4] = {};
        glGetIntegerv(GL_TEXTURE_FREE_MEMORY_ATI, free);
        if (free[0] > 0) {
            l.memory = std::size_t(free[0]) * 1024 / 4 * 3;
            l.memorySource = "3/4 of the GPU's " + bytesText(double(free[0]) * 1024.0) +
                             " of free texture memory";
        }
    }
    if (l.memory == 0) {
        const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
        const double bytes = pages > 0 && page > 0 ? double(pages) * double(page) : 8.0 * (1 << 30);
        l.memory = std::size_t(bytes / 2);
        l.memorySource = "half of the " + bytesText(bytes) + " of main memory";
    }
    return l;
}

// Whether the GL implementation can create a w x h texture of the widest target format (a proxy
// query: nothing is allocated). llvmpipe, for one, refuses textures over 1 GiB although its
// GL_MAX_TEXTURE_SIZE is 16384.
bool widestTargetFits(int w, int h) {
    glTexImage2D(GL_PROXY_TEXTURE_2D, 0, GLint(Targets::kWidestFormat), w, h, 0, GL_RGBA,
                 GL_FLOAT, nullptr);
    GLint width = 0;
    glGetTexLevelParameteriv(GL_PROXY_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &width);
    return width != 0;
}

// The largest side s in [1, hi] with fits(s) (fits is monotone); 0 when none.
template <class Fits> int largestSquare(int hi, Fits&& fits) {
    int lo = 0; // fits(lo) holds, or lo = 0
    while (lo < hi) {
        const int mid = lo + (hi - lo + 1) / 2;
        if (fits(mid)) lo = mid;
        else hi = mid - 1;
    }
    return lo;
}

// Throws geometry::InputError, before anything is allocated, for a size the GL implementation or
// the memory budget cannot hold; `bytesPerPixel` covers every per-pixel target of the frame.
void checkTargetSize(const SizeLimits& limits, int w, int h, std::size_t bytesPerPixel,
                     std::size_t budgetOverride, std::string_view method) {
    const std::string size = std::to_string(w) + "x" + std::to_string(h);
    if (w > limits.maxWidth || h > limits.maxHeight)
        throw geometry::InputError("image size " + size + " exceeds the largest render target " +
                                   "of this GL implementation, " +
                                   std::to_string(limits.maxWidth) + "x" +
                                   std::to_string(limits.maxHeight) + " (" + limits.sides + ")");
    if (!widestTargetFits(w, h)) {
        const int s = largestSquare(std::min(limits.maxWidth, limits.maxHeight),
                                    [](int side) { return widestTargetFits(side, side); });
        const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        throw geometry::InputError(
            "image size " + size + ": this GL implementation (" +
            (renderer ? renderer : "unknown") + ") cannot create a " + size +
            " RGBA32F render target (" + bytesText(double(w) * h * 16.0) +
            "); the largest square size it accepts is " + std::to_string(s) + "x" +
            std::to_string(s));
    }
    const std::size_t budget = budgetOverride ? budgetOverride : limits.memory;
    const double bytes = double(w) * double(h) * double(bytesPerPixel);
    if (bytes > double(budget)) {
        const int s = int(std::sqrt(double(budget) / double(bytesPerPixel)));
        throw geometry::InputError(
            "image size " + size + " needs about " + bytesText(bytes) + " of render targets (" +
            std::to_string(bytesPerPixel) + " bytes per pixel with method '" + std::string(method) +
            "'), more than the budget of " + bytesText(double(budget)) + " (" +
            (budgetOverride ? std::string("RenderSettings::targetMemoryBudget")
                            : limits.memorySource) +
            "); the largest square size within it is " + std::to_string(s) + "x" +
            std::to_string(s));
    }
}

} // namespace

// ---- Renderer -----------------------------------------------------------------------------------

struct Renderer::Impl {
    const geometry::Scene& scene;
    const ShaderLoader& shaders;
    std::size_t triangles = 0;
    float zNear = 0.01f;
    std::optional<geometry::RectLight> checkedLight; // the last RenderSettings::light validated
    std::optional<geometry::Camera> checkedCamera;   // the last RenderSettings::camera validated
    geometry::Aabb sceneBounds;
    SizeLimits sizeLimits = querySizeLimits();
    glm::mat4 viewProj{1.0f}; // of the last frame-uniform upload

    Buffer frameUbo{{.size = sizeof(shader::FrameUniforms), .label = "frame-uniforms"}};
    Targets targets;
    SceneGeometry sceneGeometry;
    GBufferPass gbufferPass;
    ShadePass shadePass;
    DebugViews debugViews;
    CasterSet casters;
    std::vector<std::uint32_t> allCasters;
    GpuTimers timers;
    GpuTimers frameTimer; // one span over the whole frame: FrameStats::gpuFrameMs
    // Frames that do not wait (RenderSettings::waitForGpu): the newest result of each ring and the
    // newest pair from one frame, shown until a newer pair completes.
    std::uint64_t frameIndex = 0; // of the frame being rendered, counted like GpuTimers' frames
    std::optional<GpuTimers::Deferred> newestPasses, newestWhole;
    std::vector<PassTime> shownPasses;
    double shownFrameMs = 0.0;
    std::optional<std::uint64_t> shownFrame;
    // Methods are built on first use and kept (programs, scratch targets, BVHs), one per name:
    // a method asked for with other parameters is built anew in its place.
    struct BuiltMethod {
        std::vector<ParameterValue> parameters; // resolved
        std::unique_ptr<VisibilityMethod> method;
    };
    std::map<std::string, BuiltMethod, std::less<>> methods;
    const VisibilityMethod* lastMethod = nullptr; // of the last frame (lightMasks)

    Impl(const geometry::Scene& s, const ShaderLoader& sh)
        : scene(s), shaders(sh), sceneGeometry(s), gbufferPass(sh), shadePass(sh), debugViews(sh),
          casters(s) {
        allCasters.resize(casters.size());
        std::iota(allCasters.begin(), allCasters.end(), 0u);
    }

    VisibilityMethod& method(const MethodInfo& info, std::vector<ParameterValue> parameters) {
        auto it = methods.find(info.name);
        if (it == methods.end() || it->second.parameters != parameters) {
            if (it != methods.end()) methods.erase(it); // its targets go before the new ones come
            const MethodResources resources{shaders, scene, parameters};
            // A method that occludes with whole triangles gets occlusion textures beside it for
            // the alpha-tested objects.
            auto created = !info.alphaMasks && geometry::hasAlphaTestedCasters(scene)
                               ? createAlphaComposite(resources, info)
                               : info.create(resources);
            if (targets.width > 0) created->resize(targets.width, targets.height);
            it = methods
                     .emplace(std::string(info.name),
                              BuiltMethod{std::move(parameters), std::move(created)})
                     .first;
        }
        return *it->second.method;
    }

    void uploadFrameUniforms(const RenderSettings& s, const geometry::RectLight& light,
                             float weight) {
        const geometry::Camera& cam = s.camera ? *s.camera : scene.camera;
        const float aspect = static_cast<float>(s.width) / static_cast<float>(s.height);
        shader::FrameUniforms u{};
        viewProj = infiniteReversedZ(glm::radians(cam.fovYDeg), aspect, zNear) *
                   glm::lookAt(cam.eye, cam.target, cam.up);
        u.viewProj = viewProj;
        u.eye = glm::vec4(cam.eye, 1.0f);
        u.lightCenter = glm::vec4(light.center, 1.0f);
        u.lightU = glm::vec4(light.u, 0.0f);
        u.lightV = glm::vec4(light.v, 0.0f);
        u.params = glm::vec4(s.ambient, weight, s.exposure, 0.0f);
        const glm::vec3 lu = light.u, lv = light.v;
        const glm::vec3 n = glm::normalize(glm::cross(lu, lv));
        const glm::vec3 a = glm::cross(lv, n), b = glm::cross(n, lu);
        u.lightN = glm::vec4(n, 0.0f);
        u.lightUStar = glm::vec4(a / glm::dot(lu, a), 0.0f);
        u.lightVStar = glm::vec4(b / glm::dot(lv, b), 0.0f);
        frameUbo.upload(&u, sizeof(u));
        glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_FRAME_UBO, frameUbo.id());
    }
};

Renderer::Renderer(const geometry::Scene& scene, const ShaderLoader& shaders) : mScene(scene) {
    mImpl = std::make_unique<Impl>(scene, shaders);
    for (const auto& object : scene.objects) mImpl->triangles += object.mesh.triangles.size();
    // Near plane: small against the scene so that a camera inside a level sees nearby walls.
    const geometry::Aabb b = scene.bounds();
    mImpl->sceneBounds = b;
    const float diagonal = b.empty() ? 1.0f : glm::length(b.extent());
    mImpl->zNear = std::max(1e-4f * diagonal, 1e-4f);
    checkGl("renderer setup");
}

Renderer::~Renderer() = default;

std::size_t Renderer::triangleCount() const { return mImpl->triangles; }

std::vector<ObjectInfo> Renderer::objects() const {
    std::vector<ObjectInfo> out;
    for (const auto& object : mScene.objects)
        out.push_back({object.name, object.mesh.triangles.size(),
                       object.method != geometry::ShadowMethod::None});
    const CasterSet& casters = mImpl->casters;
    for (std::size_t c = 0; c < casters.size(); ++c) {
        ObjectInfo& info = out[casters.sceneObject(c)];
        info.manifoldness = casters.topology(c).manifoldness();
        info.topology = casters.topology(c).stats();
    }
    return out;
}

FrameStats Renderer::renderFrame(const RenderSettings& settings) {
    if (settings.width < 1 || settings.height < 1)
        throw geometry::InputError("image size must be at least 1x1, got " +
                                   std::to_string(settings.width) + "x" +
                                   std::to_string(settings.height));
    const MethodInfo& info = findMethod(settings.method);
    if (info.usesSamples && settings.samples < 1)
        throw geometry::InputError("samples must be at least 1");
    std::vector<ParameterValue> parameters = resolveParameters(info, settings.parameters);
    debugViewInfo(settings.debugView); // a valid enumerator
    if (settings.debugView == DebugView::ErrorHeatMap) {
        if (settings.samples < 1) throw geometry::InputError("samples must be at least 1");
        if (settings.referenceSamplesPerFrame < 1)
            throw geometry::InputError("referenceSamplesPerFrame must be at least 1");
        if (!(settings.errorScale > 0.0f) || !std::isfinite(settings.errorScale))
            throw geometry::InputError("errorScale must be positive");
    }

    auto& m = *mImpl;
    const geometry::RectLight& light = settings.light ? *settings.light : mScene.light;
    if (settings.light && !(m.checkedLight && *m.checkedLight == light)) {
        geometry::validateLight(mScene, light, "RenderSettings::light");
        m.checkedLight = light;
    }
    if (settings.camera && !(m.checkedCamera && *m.checkedCamera == *settings.camera)) {
        geometry::validateCamera(*settings.camera, "RenderSettings::camera");
        m.checkedCamera = settings.camera;
    }
    FrameStats stats;
    stats.triangles = m.triangles;
    const auto frameStart = Clock::now();
    // Built (or kept) at the current size first, so that a new size is checked with every
    // method that will be resized, before any of it is allocated.
    VisibilityMethod& method = m.method(info, std::move(parameters));
    m.lastMethod = &method;
    if (m.targets.width != settings.width || m.targets.height != settings.height) {
        std::size_t bytesPerPixel = Targets::kBytesPerPixel + DebugViews::kBytesPerPixel;
        for (const auto& [name, each] : m.methods)
            bytesPerPixel += each.method->targetBytesPerPixel();
        checkTargetSize(m.sizeLimits, settings.width, settings.height, bytesPerPixel,
                        settings.targetMemoryBudget, info.name);
        m.targets.resize(settings.width, settings.height);
        m.debugViews.resize(m.targets);
        for (auto& [name, each] : m.methods) each.method->resize(settings.width, settings.height);
    }
    const int frameSlot = m.frameTimer.begin("frame");

    // Depth 0..1 with 1 at the near plane (reversed Z): float depth keeps precision far away.
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    m.uploadFrameUniforms(settings, light, 1.0f);

    {
        ScopedPass pass(&m.timers, "gbuffer");
        m.gbufferPass.execute(m.targets, m.sceneGeometry);
    }
    checkGl("gbuffer");

    const float zero = 0.0f;
    glClearTexImage(m.targets.visibility.id(), 0, GL_RED, GL_FLOAT, &zero);

    FrameScratch scratch;
    FrameContext ctx{settings, m.scene, light, m.targets, m.viewProj, m.casters, m.allCasters, m.timers, stats,
                     [&](float weight) { m.uploadFrameUniforms(settings, light, weight); },
                     m.sceneGeometry, &scratch};

    // Light-centre silhouettes, uploaded once: every method reports them, most draw from them.
    auto t0 = Clock::now();
    m.casters.update(light, m.sceneBounds);
    ctx.addCpuTime("silhouettes", msSince(t0));
    stats.silhouetteEdges = m.casters.edgeCount();
    stats.silhouetteGroups = m.casters.groupCount();
    stats.volumeTriangles = 2 * static_cast<std::size_t>(m.casters.triangleCount()) +
                            2 * static_cast<std::size_t>(m.casters.edgeCount());
    stats.silhouetteUploadBytes = m.casters.uploadBytes();
    std::size_t containing = 0; // closed casters around the light centre (drawn two-sided)
    for (std::size_t c = 0; c < m.casters.size(); ++c) containing += m.casters.frame(c).lightInside;
    ctx.addCounter("casters_containing_light", static_cast<double>(containing));

    method.execute(ctx);
    checkGl("visibility");

    {
        ScopedPass pass(&m.timers, "shade");
        m.shadePass.execute(m.targets);
    }
    checkGl("shade");
    if (settings.debugView != DebugView::Shaded) {
        ScopedPass pass(&m.timers, "debug-view");
        m.debugViews.draw(ctx, method, info.name);
        stats.debugNote = m.debugViews.note;
        checkGl("debug view");
    }
    m.frameTimer.end(frameSlot);
    if (settings.waitForGpu) {
        ++m.frameIndex; // as the rings count their frames
        glFinish();
        stats.frameMs = msSince(frameStart);
        stats.gpu = m.timers.resolve();
        const std::vector<PassTime> whole = m.frameTimer.resolve();
        stats.gpuFrameMs = whole.empty() ? 0.0 : whole.front().ms;
        return stats;
    }
    // Submitted, not waited for: the viewer's buffer swap flushes too, but a headless caller
    // that does not wait would leave the frame queued (llvmpipe runs nothing until a flush), and
    // its timer queries would complete only when some later frame fills the queue.
    glFlush();
    // The two rings complete independently (a frame's passes end before its span does): each
    // keeps its newest result, and the frame reports the newest pair measured in one frame.
    stats.frameMs = msSince(frameStart);
    const std::uint64_t thisFrame = m.frameIndex++;
    if (auto passes = m.timers.resolveDeferred()) m.newestPasses = std::move(passes);
    if (auto whole = m.frameTimer.resolveDeferred()) m.newestWhole = std::move(whole);
    if (m.newestPasses && m.newestWhole && m.newestPasses->frame == m.newestWhole->frame) {
        m.shownPasses = m.newestPasses->passes;
        m.shownFrameMs = m.newestWhole->passes.empty() ? 0.0 : m.newestWhole->passes.front().ms;
        m.shownFrame = m.newestWhole->frame;
    }
    stats.gpuTimesLag = -1;
    if (m.shownFrame) {
        stats.gpu = m.shownPasses;
        stats.gpuFrameMs = m.shownFrameMs;
        stats.gpuTimesLag = static_cast<int>(thisFrame - *m.shownFrame);
    }
    return stats;
}

namespace {

// GL rows run bottom to top; our images run top to bottom.
void flipRows(std::vector<float>& data, int width, int height, int channels) {
    const std::size_t row = static_cast<std::size_t>(width) * channels;
    for (int y = 0; y < height / 2; ++y)
        std::swap_ranges(data.begin() + y * row, data.begin() + (y + 1) * row,
                         data.begin() + (height - 1 - y) * row);
}

} // namespace

geometry::FloatImage Renderer::visibility() const {
    const auto& t = mImpl->targets;
    geometry::FloatImage img{t.width, t.height, 1, t.visibility.readFloat(1)};
    const std::vector<float> pos = t.position.readFloat(4);
    for (std::size_t i = 0; i < img.data.size(); ++i)
        if (pos[4 * i + 3] == 0.0f) img.data[i] = std::numeric_limits<float>::quiet_NaN();
    flipRows(img.data, t.width, t.height, 1);
    return img;
}

LightMasks Renderer::lightMasks() const {
    return mImpl->lastMethod ? mImpl->lastMethod->lightMasks() : LightMasks{};
}

geometry::FloatImage Renderer::referenceVisibility() const {
    const auto& t = mImpl->targets;
    const Texture& sum = mImpl->debugViews.referenceSum();
    if (!sum.id()) return {};
    geometry::FloatImage img{t.width, t.height, 1, sum.readFloat(1)};
    const float scale = mImpl->debugViews.referenceScale();
    const std::vector<float> pos = t.position.readFloat(4);
    for (std::size_t i = 0; i < img.data.size(); ++i)
        img.data[i] = pos[4 * i + 3] == 0.0f ? std::numeric_limits<float>::quiet_NaN()
                                             : img.data[i] * scale;
    flipRows(img.data, t.width, t.height, 1);
    return img;
}

namespace {

geometry::FloatImage readXyz(const Texture& texture, const Texture& position) {
    const std::vector<float> src = texture.readFloat(4);
    const std::vector<float> pos = position.readFloat(4);
    geometry::FloatImage img{texture.width(), texture.height(), 3, {}};
    img.data.resize(static_cast<std::size_t>(img.width) * img.height * 3);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t i = 0; i < img.data.size() / 3; ++i)
        for (int c = 0; c < 3; ++c)
            img.data[3 * i + c] = pos[4 * i + 3] != 0.0f ? src[4 * i + c] : nan;
    flipRows(img.data, img.width, img.height, 3);
    return img;
}

} // namespace

geometry::FloatImage Renderer::position() const {
    return readXyz(mImpl->targets.position, mImpl->targets.position);
}

geometry::FloatImage Renderer::normal() const {
    return readXyz(mImpl->targets.normal, mImpl->targets.position);
}

std::vector<std::uint8_t> Renderer::imageRgba8() const {
    const auto& t = mImpl->targets;
    std::vector<std::byte> raw;
    t.image.read(GL_RGBA, GL_UNSIGNED_BYTE, raw);
    std::vector<std::uint8_t> out(raw.size());
    const std::size_t row = static_cast<std::size_t>(t.width) * 4;
    for (int y = 0; y < t.height; ++y)
        std::memcpy(out.data() + y * row, raw.data() + (t.height - 1 - y) * row, row);
    return out;
}

void Renderer::blitImage(int x, int y, int width, int height, unsigned int framebuffer) const {
    const auto& t = mImpl->targets;
    if (t.width == 0) return; // no frame yet
    // A blit honours the scissor test (and, on some drivers, the colour mask): off for it, then
    // back as the caller had them. The image holds sRGB-encoded bytes: the target must not
    // encode again (GL_FRAMEBUFFER_SRGB off).
    const GLboolean scissor = glIsEnabled(GL_SCISSOR_TEST);
    GLboolean mask[4];
    glGetBooleani_v(GL_COLOR_WRITEMASK, 0, mask);
    glDisable(GL_SCISSOR_TEST);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glBlitNamedFramebuffer(t.imageFbo.id(), framebuffer, 0, 0, t.width, t.height, x, y, x + width,
                           y + height, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    glColorMaski(0, mask[0], mask[1], mask[2], mask[3]);
    if (scissor) glEnable(GL_SCISSOR_TEST);
}

} // namespace gpu
