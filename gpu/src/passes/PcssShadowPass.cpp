#include "passes/PcssShadowPass.h"

#include "engine/ShaderBindings.h"

#include <string>
#include <vector>

namespace gpu {

namespace {

Program loadShadowProgram(const ShaderLoader& shaders, bool alphaTested) {
    return shaders.load({.stages = {{GL_VERTEX_SHADER, "pcss-shadow.vert"},
                                    {GL_FRAGMENT_SHADER, "pcss-shadow.frag"}},
                         // The base level, as raytrace's alpha rule and the reach test's boxes
                         // (geometry::occlusionBounds) read it: a mip level's averaged alpha
                         // would move leaf edges and let a card occlude beyond its boxes.
                         .defines = alphaTested
                                        ? std::vector<std::string>{"ALPHA_TEST",
                                                                   "MATERIAL_BASE_LEVEL"}
                                        : std::vector<std::string>{},
                         .label = alphaTested ? "pcss-shadow-alpha-test" : "pcss-shadow"});
}

} // namespace

PcssShadowPass::PcssShadowPass(const ShaderLoader& shaders)
    : mOpaque(loadShadowProgram(shaders, false)), mAlphaTested(loadShadowProgram(shaders, true)) {}

void PcssShadowPass::execute(const Framebuffer& target, int face, int resolution,
                             const SceneGeometry& geometry,
                             std::span<const std::size_t> objects) const {
    applyState(kState);
    glBindFramebuffer(GL_FRAMEBUFFER, target.id());
    glViewport(0, 0, resolution, resolution);
    const float nothing = 0.0f; // depth 0: infinitely far
    glClearNamedFramebufferfv(target.id(), GL_DEPTH, 0, &nothing);
    for (const Program* p : {&mOpaque, &mAlphaTested})
        glProgramUniform1i(p->id(), UNIFORM_PCSS_SIDE, face);
    // The opaque variant reads no material (its uniforms are optimised out).
    const SceneGeometry::Programs programs{mOpaque, mAlphaTested, false};
    for (const std::size_t object : objects)
        geometry.drawObject(object, programs);
}

} // namespace gpu
