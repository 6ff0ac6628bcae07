// Renderer: the frame of penumbra-render, in a fixed order.
// - G-buffer: world position, viewer-facing normal, albedo, reversed-Z depth + stencil;
// - visibility: z-fail stencil shadow volumes from the light centre (hard), averaged over
//   stratified light samples (reference), or Embree rays at the G-buffer positions (raytrace);
// - shade: albedo * (ambient + V * n.l).
#include <gpu/Renderer.h>

#include <geometry/Error.h>
#include <geometry/RayTracer.h>
#include <geometry/Sampling.h>
#include <geometry/ShadowVolume.h>
#include <geometry/Silhouette.h>
#include <geometry/Topology.h>
#include <gpu/State.h>

#include "ShaderBindings.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstring>
#include <cmath>
#include <limits>

namespace gpu {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Adds `ms` to the stage `name` (stages repeat per light sample in the reference).
void addCpuTime(std::vector<CpuTime>& times, std::string_view name, double ms) {
    for (auto& t : times)
        if (t.name == name) {
            t.ms += ms;
            return;
        }
    times.push_back({std::string(name), ms});
}

// ---- Fixed-function state, one per pass (STYLE.md: state is data) ----------------------------

constexpr PipelineState kGBufferState{
    .depthTest = true,
    .depthFunc = GL_GREATER, // reversed Z
    .depthWrite = true,
};

// z-fail (Carmack): count volume faces *behind* the visible surface, +1 for back faces (the eye
// ray leaves a volume there) and -1 for front faces; the camera may sit inside a volume.
// Wrapping ops: counts may go negative transiently; only the final zero/non-zero matters.
constexpr PipelineState kVolumeState{
    .depthTest = true,
    .depthFunc = GL_GREATER,
    .depthWrite = false,
    .colorWrite = false,
    .stencilTest = true,
    .stencilFront = {.func = GL_ALWAYS, .depthFail = GL_DECR_WRAP},
    .stencilBack = {.func = GL_ALWAYS, .depthFail = GL_INCR_WRAP},
    .cull = false,
    // Depth clamp instead of near/far clipping: a volume face between the camera and the near
    // plane still counts as "in front", and the back cap at depth 0 is never clipped.
    .depthClamp = true,
};

// Front caps coincide with the surfaces they come from. The surface must count as outside its
// own cap (lit when it faces the light), so the caps are pushed slightly away from the camera:
// the G-buffer and volume shaders cannot be made bitwise identical across compilers.
constexpr PipelineState kVolumeCapState = [] {
    PipelineState s = kVolumeState;
    s.polygonOffset = true;
    s.polygonOffsetFactor = -1.0f; // reversed Z: negative = farther
    s.polygonOffsetUnits = -4.0f;
    return s;
}();

constexpr PipelineState kAccumulateState{
    .stencilTest = true,
    .stencilWriteMask = 0,
    .stencilFront = {.func = GL_EQUAL, .ref = 0},
    .stencilBack = {.func = GL_EQUAL, .ref = 0},
    .blend = true,
    .blendSrc = GL_ONE,
    .blendDst = GL_ONE,
};

constexpr PipelineState kFullscreenState{};

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

struct SceneVertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec3 albedo;
};

bool hasAlphaCutout(const geometry::MeshData& mesh) {
    return std::any_of(mesh.materials.begin(), mesh.materials.end(), [](const auto& m) {
        return m.alphaMode != geometry::AlphaMode::Opaque;
    });
}

} // namespace

const std::vector<std::string>& allMethodNames() {
    static const std::vector<std::string> names = {
        "hard",  "reference",      "raytrace",  "wedges-additive", "wedges-blend",
        "wedges-multiply", "occlusion", "pcss", "auto"};
    return names;
}

Method parseMethod(const std::string& name) {
    if (name == "hard") return Method::Hard;
    if (name == "reference") return Method::Reference;
    if (name == "raytrace") return Method::Raytrace;
    const auto& all = allMethodNames();
    if (std::find(all.begin(), all.end(), name) != all.end())
        throw geometry::InputError("method '" + name +
                                   "' is part of the render contract but not implemented yet; "
                                   "implemented: hard, reference, raytrace");
    std::string list;
    for (const auto& n : all) list += (list.empty() ? "" : ", ") + n;
    throw geometry::InputError("unknown method '" + name + "' (known: " + list + ")");
}

const char* toString(Method m) {
    switch (m) {
    case Method::Hard: return "hard";
    case Method::Reference: return "reference";
    case Method::Raytrace: return "raytrace";
    }
    return "?";
}

// ---- Passes -------------------------------------------------------------------------------------

namespace {

// Render targets shared by the passes; recreated on resize.
struct Targets {
    int width = 0, height = 0;
    Texture depthStencil, position, normal, albedo, visibility, image;
    Framebuffer gbuffer, visibilityFbo, imageFbo;

    void resize(int w, int h) {
        width = w;
        height = h;
        depthStencil = Texture({.width = w, .height = h, .format = GL_DEPTH32F_STENCIL8,
                                .label = "depth-stencil"});
        position = Texture({.width = w, .height = h, .format = GL_RGBA32F, .label = "g-position"});
        normal = Texture({.width = w, .height = h, .format = GL_RGBA32F, .label = "g-normal"});
        albedo = Texture({.width = w, .height = h, .format = GL_RGBA8, .label = "g-albedo"});
        visibility = Texture({.width = w, .height = h, .format = GL_R32F, .label = "visibility"});
        image = Texture({.width = w, .height = h, .format = GL_RGBA8, .label = "image"});
        gbuffer = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &position},
                                               {GL_COLOR_ATTACHMENT1, &normal},
                                               {GL_COLOR_ATTACHMENT2, &albedo},
                                               {GL_DEPTH_STENCIL_ATTACHMENT, &depthStencil}},
                               .label = "gbuffer"});
        visibilityFbo = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &visibility},
                                                     {GL_DEPTH_STENCIL_ATTACHMENT, &depthStencil}},
                                     .label = "visibility"});
        imageFbo = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &image}}, .label = "image"});
    }
};

// G-buffer of every object (casters and receivers alike).
class GBufferPass {
public:
    GBufferPass(const ShaderLoader& shaders, std::span<const SceneVertex> vertices)
        : mProgram(shaders.load({.stages = {{GL_VERTEX_SHADER, "gbuffer.vert"},
                                            {GL_FRAGMENT_SHADER, "gbuffer.frag"}},
                                 .label = "gbuffer"})),
          mVertices({.size = vertices.size_bytes(), .data = vertices.data(), .flags = 0,
                     .label = "scene-vertices"}),
          mVao("scene"), mCount(static_cast<GLsizei>(vertices.size())) {
        mVao.vertexBuffer(0, mVertices, 0, sizeof(SceneVertex));
        mVao.attribute(0, 0, 3, GL_FLOAT, offsetof(SceneVertex, position));
        mVao.attribute(1, 0, 3, GL_FLOAT, offsetof(SceneVertex, normal));
        mVao.attribute(2, 0, 3, GL_FLOAT, offsetof(SceneVertex, albedo));
    }

    void execute(const Targets& t) {
        applyState(kGBufferState);
        glBindFramebuffer(GL_FRAMEBUFFER, t.gbuffer.id());
        glViewport(0, 0, t.width, t.height);
        const float zero[4] = {0, 0, 0, 0};
        for (int i = 0; i < 3; ++i) glClearNamedFramebufferfv(t.gbuffer.id(), GL_COLOR, i, zero);
        glClearNamedFramebufferfi(t.gbuffer.id(), GL_DEPTH_STENCIL, 0, 0.0f, 0); // reversed Z
        glUseProgram(mProgram.id());
        glBindVertexArray(mVao.id());
        glDrawArrays(GL_TRIANGLES, 0, mCount);
    }

private:
    Program mProgram;
    Buffer mVertices;
    VertexArray mVao;
    GLsizei mCount;
};

// z-fail stencil counts of one light point's shadow volumes into the shared stencil buffer.
class StencilVolumePass {
public:
    explicit StencilVolumePass(const ShaderLoader& shaders)
        : mProgram(shaders.load({.stages = {{GL_VERTEX_SHADER, "volume.vert"},
                                            {GL_GEOMETRY_SHADER, "volume.geom"},
                                            {GL_FRAGMENT_SHADER, "volume.frag"}},
                                 .label = "shadow-volume"})),
          mVao("shadow-volume") {
        mVao.attribute(0, 0, 4, GL_FLOAT, 0);
    }

    // `frontCapVertices` leading vertices of `volume` are front caps (drawn with the cap offset).
    void execute(const Targets& t, const geometry::ShadowVolumeGeometry& volume,
                 std::size_t frontCapVertices) {
        if (volume.vertices.empty()) return;
        mVertices.uploadResize(volume.vertices.data(), volume.vertices.size() * sizeof(glm::vec4));
        mVao.vertexBuffer(0, mVertices, 0, sizeof(glm::vec4));
        glBindFramebuffer(GL_FRAMEBUFFER, t.visibilityFbo.id());
        glViewport(0, 0, t.width, t.height);
        glUseProgram(mProgram.id());
        glBindVertexArray(mVao.id());
        applyState(kVolumeCapState);
        glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(frontCapVertices));
        applyState(kVolumeState);
        glDrawArrays(GL_TRIANGLES, static_cast<GLint>(frontCapVertices),
                     static_cast<GLsizei>(volume.vertices.size() - frontCapVertices));
    }

private:
    Program mProgram;
    VertexArray mVao;
    Buffer mVertices;
};

// One triangle over the viewport with a fragment shader, a fixed state and a target.
class FullscreenPass {
public:
    FullscreenPass(const ShaderLoader& shaders, const char* fragment, const char* label,
                   const PipelineState& state)
        : mProgram(shaders.load({.stages = {{GL_VERTEX_SHADER, "fullscreen.vert"},
                                            {GL_FRAGMENT_SHADER, fragment}},
                                 .label = label})),
          mVao(label), mState(state) {}

    void execute(const Framebuffer& target, int width, int height) {
        applyState(mState);
        glBindFramebuffer(GL_FRAMEBUFFER, target.id());
        glViewport(0, 0, width, height);
        glUseProgram(mProgram.id());
        glBindVertexArray(mVao.id());
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }

private:
    Program mProgram;
    VertexArray mVao;
    PipelineState mState;
};

// Writes frame.params.y into V where the stencil count is zero (lit).
class AccumulatePass {
public:
    explicit AccumulatePass(const ShaderLoader& shaders)
        : mPass(shaders, "accumulate.frag", "accumulate", kAccumulateState) {}
    void execute(const Targets& t) { mPass.execute(t.visibilityFbo, t.width, t.height); }

private:
    FullscreenPass mPass;
};

// The image from the G-buffer and V.
class ShadePass {
public:
    explicit ShadePass(const ShaderLoader& shaders)
        : mPass(shaders, "shade.frag", "shade", kFullscreenState) {}
    void execute(const Targets& t) {
        glBindTextureUnit(TEXUNIT_POSITION, t.position.id());
        glBindTextureUnit(TEXUNIT_NORMAL, t.normal.id());
        glBindTextureUnit(TEXUNIT_ALBEDO, t.albedo.id());
        glBindTextureUnit(TEXUNIT_VISIBILITY, t.visibility.id());
        mPass.execute(t.imageFbo, t.width, t.height);
    }

private:
    FullscreenPass mPass;
};

} // namespace

// ---- Renderer -----------------------------------------------------------------------------------

struct Renderer::Impl {
    const geometry::Scene& scene;
    std::vector<geometry::Topology> casters; // objects whose method is not None
    std::size_t triangles = 0;
    float zNear = 0.01f;

    Buffer frameUbo{{.size = sizeof(shader::FrameUniforms), .label = "frame-uniforms"}};
    Targets targets;
    GBufferPass gbufferPass;
    StencilVolumePass volumePass;
    AccumulatePass accumulatePass;
    ShadePass shadePass;
    GpuTimers timers;

    // Per-frame silhouettes from the light centre (topology once, groups/loops/volumes per
    // light; reused while the light does not move). Built after `casters` is final.
    std::vector<geometry::SilhouetteExtractor> extractors;
    geometry::Aabb sceneBounds;

    geometry::ShadowVolumeGeometry volume;
    geometry::ShadowVolumeGeometry part; // scratch: one caster's volume
    std::vector<glm::vec4> rest;         // scratch: back caps and sides, after the front caps
    std::unique_ptr<geometry::RayTracer> rayTracer; // built on first raytrace frame

    Impl(const geometry::Scene& s, const ShaderLoader& shaders, std::vector<SceneVertex> vertices)
        : scene(s), gbufferPass(shaders, vertices), volumePass(shaders), accumulatePass(shaders),
          shadePass(shaders) {}

    // Volumes of every caster for one light point; front caps first (see StencilVolumePass).
    std::size_t buildVolume(const glm::vec3& light) {
        // Two passes over the casters keep all front caps contiguous at the start.
        volume.clear();
        rest.clear();
        std::size_t frontCapVertices = 0;
        for (const auto& topology : casters) {
            part.clear();
            geometry::appendHardShadowVolume(topology, light, part);
            const std::size_t front = 3 * topology.triangles().size();
            volume.vertices.insert(volume.vertices.end(), part.vertices.begin(),
                                   part.vertices.begin() + static_cast<std::ptrdiff_t>(front));
            rest.insert(rest.end(), part.vertices.begin() + static_cast<std::ptrdiff_t>(front),
                        part.vertices.end());
            frontCapVertices += front;
            volume.capTriangles += part.capTriangles;
            volume.sideTriangles += part.sideTriangles;
            volume.silhouetteEdges += part.silhouetteEdges;
        }
        volume.vertices.insert(volume.vertices.end(), rest.begin(), rest.end());
        return frontCapVertices;
    }

    // The light-centre volume from the silhouette groups (the hard method); front caps first.
    // Returns the number of front-cap vertices and fills group/edge counts into `stats`.
    std::size_t buildCentreVolume(FrameStats& stats) {
        volume.clear();
        rest.clear();
        std::size_t frontCapVertices = 0;
        geometry::SilhouetteSettings settings;
        settings.buildWedges = false; // hard shadows need the volumes only
        settings.capVertices = true;  // this pass draws caps from vertices (no vertex pulling)
        for (auto& extractor : extractors) {
            const geometry::SilhouetteFrame& f = extractor.update(scene.light, sceneBounds,
                                                                  settings);
            stats.silhouetteGroups += f.groups.size();
            stats.silhouetteEdges += f.edges.size();
            for (const auto& g : f.groups) {
                const auto first = f.volumeVertices.begin() + g.firstVolumeVertex;
                volume.vertices.insert(volume.vertices.end(), first,
                                       first + g.frontCapVertexCount);
                rest.insert(rest.end(), first + g.frontCapVertexCount,
                            first + g.volumeVertexCount);
                frontCapVertices += g.frontCapVertexCount;
            }
        }
        volume.vertices.insert(volume.vertices.end(), rest.begin(), rest.end());
        return frontCapVertices;
    }

    void uploadFrameUniforms(const RenderSettings& s, float weight) {
        const auto& cam = scene.camera;
        const float aspect = static_cast<float>(s.width) / static_cast<float>(s.height);
        shader::FrameUniforms u{};
        u.viewProj = infiniteReversedZ(glm::radians(cam.fovYDeg), aspect, zNear) *
                     glm::lookAt(cam.eye, cam.target, cam.up);
        u.eye = glm::vec4(cam.eye, 1.0f);
        u.lightCenter = glm::vec4(scene.light.center, 1.0f);
        u.lightU = glm::vec4(scene.light.u, 0.0f);
        u.lightV = glm::vec4(scene.light.v, 0.0f);
        u.params = glm::vec4(s.ambient, weight, s.exposure, 0.0f);
        frameUbo.upload(&u, sizeof(u));
        glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_FRAME_UBO, frameUbo.id());
    }
};

namespace {

std::vector<SceneVertex> expandSceneVertices(const geometry::Scene& scene) {
    std::vector<SceneVertex> out;
    out.reserve(3 * scene.triangleCount());
    for (const auto& object : scene.objects) {
        const auto& mesh = object.mesh;
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            const glm::uvec3 tri = mesh.triangles[t];
            const glm::vec3 a = mesh.positions[tri.x], b = mesh.positions[tri.y],
                            c = mesh.positions[tri.z];
            const glm::vec3 n = glm::cross(b - a, c - a);
            const float len = glm::length(n);
            if (!(len > 0.0f)) continue; // zero area: rasterises nothing, has no normal
            glm::vec3 albedo(0.8f);
            if (!mesh.triangleMaterial.empty() && !mesh.materials.empty())
                albedo = glm::vec3(mesh.materials[mesh.triangleMaterial[t]].baseColor);
            for (const glm::vec3& p : {a, b, c}) out.push_back({p, n / len, albedo});
        }
    }
    return out;
}

} // namespace

Renderer::Renderer(const geometry::Scene& scene, const ShaderLoader& shaders) : mScene(scene) {
    for (const auto& object : scene.objects) {
        if (object.method != geometry::ShadowMethod::None && hasAlphaCutout(object.mesh))
            throw geometry::InputError(
                "object '" + object.name +
                "' has alpha-masked or blended materials: no implemented method shadows with "
                "alpha cut-outs yet (shadow volumes would treat the cards as opaque); give it "
                "\"method\": \"none\" to render it unshadowing");
    }
    mImpl = std::make_unique<Impl>(scene, shaders, expandSceneVertices(scene));
    for (const auto& object : scene.objects) {
        mImpl->triangles += object.mesh.triangles.size();
        if (object.method != geometry::ShadowMethod::None) mImpl->casters.emplace_back(object.mesh);
    }
    mImpl->extractors.reserve(mImpl->casters.size());
    for (const auto& topology : mImpl->casters) mImpl->extractors.emplace_back(topology);
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
    std::size_t caster = 0;
    for (const auto& object : mScene.objects) {
        ObjectInfo info{object.name, object.mesh.triangles.size(),
                        object.method != geometry::ShadowMethod::None};
        if (info.casts) {
            const geometry::Topology& t = mImpl->casters[caster++];
            info.manifoldness = t.manifoldness();
            info.topology = t.stats();
        }
        out.push_back(std::move(info));
    }
    return out;
}

FrameStats Renderer::renderFrame(const RenderSettings& settings) {
    if (settings.width < 1 || settings.height < 1 || settings.width > 16384 ||
        settings.height > 16384)
        throw geometry::InputError("image size must be between 1x1 and 16384x16384");
    if (settings.method != Method::Hard && settings.samples < 1)
        throw geometry::InputError("samples must be at least 1");

    auto& m = *mImpl;
    FrameStats stats;
    stats.triangles = m.triangles;
    const auto frameStart = Clock::now();
    if (m.targets.width != settings.width || m.targets.height != settings.height)
        m.targets.resize(settings.width, settings.height);

    // Depth 0..1 with 1 at the near plane (reversed Z): float depth keeps precision far away.
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    m.uploadFrameUniforms(settings, 1.0f);

    {
        ScopedPass pass(&m.timers, "gbuffer");
        m.gbufferPass.execute(m.targets);
    }
    checkGl("gbuffer");

    const float zero = 0.0f;
    glClearTexImage(m.targets.visibility.id(), 0, GL_RED, GL_FLOAT, &zero);

    // Light-centre silhouettes and volume: the hard method draws it, every method reports it.
    auto t0 = Clock::now();
    std::size_t frontCaps = m.buildCentreVolume(stats);
    addCpuTime(stats.cpu, "silhouettes", msSince(t0));
    stats.volumeTriangles = m.volume.vertices.size() / 3;

    switch (settings.method) {
    case Method::Hard: {
        {
            ScopedPass pass(&m.timers, "shadow-volume");
            m.volumePass.execute(m.targets, m.volume, frontCaps);
        }
        ScopedPass pass(&m.timers, "accumulate");
        m.accumulatePass.execute(m.targets);
        break;
    }
    case Method::Reference: {
        // N exact hard-shadow passes from stratified points of the light, each adding 1/N where
        // lit (DESIGN.md §4 "Reference").
        const auto samples = geometry::stratifiedSquare(settings.samples, settings.seed);
        m.uploadFrameUniforms(settings, 1.0f / static_cast<float>(samples.size()));
        const int total = static_cast<int>(samples.size());
        const int step = std::max(1, total / 10);
        for (int i = 0; i < total; ++i) {
            const glm::vec3 light = m.scene.light.point(samples[i].x, samples[i].y);
            t0 = Clock::now();
            frontCaps = m.buildVolume(light);
            addCpuTime(stats.cpu, "shadow-volume-build", msSince(t0));
            {
                ScopedPass pass(&m.timers, "shadow-volume");
                const int zeroStencil = 0;
                applyState(kVolumeState); // stencil write mask on for the clear
                glClearNamedFramebufferiv(m.targets.visibilityFbo.id(), GL_STENCIL, 0,
                                          &zeroStencil);
                m.volumePass.execute(m.targets, m.volume, frontCaps);
            }
            {
                ScopedPass pass(&m.timers, "accumulate");
                m.accumulatePass.execute(m.targets);
            }
            if (settings.progress && ((i + 1) % step == 0 || i + 1 == total)) {
                glFinish(); // progress should reflect finished work, not queued commands
                settings.progress(i + 1, total);
            }
        }
        break;
    }
    case Method::Raytrace: {
        if (!m.rayTracer) {
            t0 = Clock::now();
            m.rayTracer = std::make_unique<geometry::RayTracer>(m.scene);
            addCpuTime(stats.cpu, "raytrace-build", msSince(t0));
        }
        t0 = Clock::now();
        const std::vector<float> pos = m.targets.position.readFloat(4);
        const std::vector<float> nrm = m.targets.normal.readFloat(4);
        const std::size_t n = static_cast<std::size_t>(settings.width) * settings.height;
        std::vector<glm::vec3> points(n), normals(n);
        const float nan = std::numeric_limits<float>::quiet_NaN();
        for (std::size_t i = 0; i < n; ++i) {
            const bool surface = pos[4 * i + 3] != 0.0f;
            points[i] = surface ? glm::vec3(pos[4 * i], pos[4 * i + 1], pos[4 * i + 2])
                                : glm::vec3(nan);
            normals[i] = glm::vec3(nrm[4 * i], nrm[4 * i + 1], nrm[4 * i + 2]);
        }
        addCpuTime(stats.cpu, "gbuffer-readback", msSince(t0));
        t0 = Clock::now();
        std::vector<float> v(n);
        geometry::RayTraceSettings rt;
        rt.samples = settings.samples;
        rt.seed = settings.seed;
        m.rayTracer->visibility(m.scene.light, points, normals, rt, v);
        addCpuTime(stats.cpu, "raytrace", msSince(t0));
        glTextureSubImage2D(m.targets.visibility.id(), 0, 0, 0, settings.width, settings.height,
                            GL_RED, GL_FLOAT, v.data());
        break;
    }
    }
    checkGl("visibility");

    {
        ScopedPass pass(&m.timers, "shade");
        m.shadePass.execute(m.targets);
    }
    checkGl("shade");
    glFinish();
    stats.frameMs = msSince(frameStart);
    stats.gpu = m.timers.resolve();
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

} // namespace gpu
