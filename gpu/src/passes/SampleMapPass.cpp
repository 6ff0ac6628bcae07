#include "passes/SampleMapPass.h"

#include "engine/ShaderBindings.h"

#include <geometry/core/Sampling.h>
#include <gpu/gl/State.h>

#include <string>

namespace gpu {

namespace {

Program loadMapProgram(const ShaderLoader& shaders, bool alphaTested) {
    std::vector<std::string> defines = {"SAMPLE_MAP"};
    if (alphaTested) {
        defines.push_back("ALPHA_TEST");
        defines.push_back("MATERIAL_BASE_LEVEL");
    }
    return shaders.load({.stages = {{GL_VERTEX_SHADER, "pcss-shadow.vert"},
                                    {GL_FRAGMENT_SHADER, "pcss-shadow.frag"}},
                         .defines = defines,
                         .label = alphaTested ? "sample-map-alpha-test" : "sample-map"});
}

// Depth only, zNear / z reversed (cleared to 0, GREATER keeps the nearest), no culling: every
// triangle occludes from both sides, as in pcss's maps.
constexpr PipelineState kMapState{
    .depthTest = true, .depthFunc = GL_GREATER, .depthWrite = true, .colorWrite = false};

} // namespace

SampleMapPass::SampleMapPass(const ShaderLoader& shaders, int layers, int resolution,
                             const char* label)
    : mOpaque(loadMapProgram(shaders, false)), mAlphaTested(loadMapProgram(shaders, true)),
      mResolution(resolution), mLayers(layers) {
    mMaps = Texture({.target = GL_TEXTURE_2D_ARRAY,
                     .width = resolution,
                     .height = resolution,
                     .layers = layers,
                     .format = GL_DEPTH_COMPONENT32F,
                     .wrap = GL_CLAMP_TO_BORDER,
                     .label = label});
    for (int i = 0; i < layers; ++i)
        mFbos.emplace_back(FramebufferDesc{.attachments = {{GL_DEPTH_ATTACHMENT, &mMaps, 0, i}},
                                           .label = label});
}

void SampleMapPass::draw(const geometry::SampleMapFrame& frame, std::size_t first,
                         std::size_t count, std::span<const std::size_t> objects,
                         const SceneGeometry& geometry, float slopeBias) const {
    applyState(kMapState);
    // Reversed depth (zNear / z): farther is smaller, so the offset is negative.
    if (slopeBias > 0.0f) {
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(-slopeBias, -1.0f);
    }
    const SceneGeometry::Programs programs{mOpaque, mAlphaTested, false};
    const float nothing = 0.0f;
    for (std::size_t k = 0; k < count; ++k) {
        const Framebuffer& fbo = mFbos[k];
        glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
        glViewport(0, 0, mResolution, mResolution);
        glClearNamedFramebufferfv(fbo.id(), GL_DEPTH, 0, &nothing);
        const glm::mat4 m = frame.projection(first + k);
        for (const Program* p : {&mOpaque, &mAlphaTested})
            glProgramUniformMatrix4fv(p->id(), UNIFORM_SAMPLE_MAP_VIEW, 1, GL_FALSE, &m[0][0]);
        for (const std::size_t object : objects) geometry.drawObject(object, programs);
    }
    if (slopeBias > 0.0f) {
        glPolygonOffset(0.0f, 0.0f);
        glDisable(GL_POLYGON_OFFSET_FILL);
    }
}

SampleMapSetup fitSampleMaps(const geometry::Scene& scene, const CasterSet& casters,
                             std::span<const std::uint32_t> casterSubset,
                             const geometry::RectLight& light, int samples, std::uint32_t seed) {
    const std::vector<glm::vec2> points = geometry::stratifiedSquare(samples, seed);
    return fitSampleMaps(scene, casters, casterSubset, light, points);
}

SampleMapSetup fitSampleMaps(const geometry::Scene& scene, const CasterSet& casters,
                             std::span<const std::uint32_t> casterSubset,
                             const geometry::RectLight& light, std::span<const glm::vec2> points) {
    SampleMapSetup s;
    for (const std::uint32_t c : casterSubset) {
        const std::size_t object = casters.sceneObject(c);
        s.objects.push_back(object);
        s.bounds.extend(scene.objects[object].mesh.bounds());
    }
    s.frame = geometry::fitSampleMapFrame(light, points, s.bounds);
    return s;
}

} // namespace gpu
