#include "passes/GBufferPass.h"

namespace gpu {

namespace {

Program load(const ShaderLoader& shaders, bool alphaTested) {
    return shaders.load({.stages = {{GL_VERTEX_SHADER, "gbuffer.vert"},
                                    {GL_FRAGMENT_SHADER, "gbuffer.frag"}},
                         .defines = alphaTested ? std::vector<std::string>{"ALPHA_TEST"}
                                                : std::vector<std::string>{},
                         .label = alphaTested ? "gbuffer-alpha-test" : "gbuffer"});
}

} // namespace

GBufferPass::GBufferPass(const ShaderLoader& shaders)
    : mOpaque(load(shaders, false)), mAlphaTested(load(shaders, true)) {}

void GBufferPass::execute(const Targets& t, const SceneGeometry& geometry) {
    applyState(kState);
    glBindFramebuffer(GL_FRAMEBUFFER, t.gbuffer.id());
    glViewport(0, 0, t.width, t.height);
    const float zero[4] = {0, 0, 0, 0};
    for (int i = 0; i < 4; ++i) glClearNamedFramebufferfv(t.gbuffer.id(), GL_COLOR, i, zero);
    glClearNamedFramebufferfi(t.gbuffer.id(), GL_DEPTH_STENCIL, 0, 0.0f, 0); // reversed Z
    geometry.drawAll({mOpaque, mAlphaTested});
}

} // namespace gpu
