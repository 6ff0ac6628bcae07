#include "passes/FullscreenPass.h"

namespace gpu {

FullscreenPass::FullscreenPass(const ShaderLoader& shaders, const char* fragment,
                               const char* label, const PipelineState& state,
                               std::vector<std::string> defines, const char* vertex)
    : mProgram(shaders.load({.stages = {{GL_VERTEX_SHADER, vertex},
                                        {GL_FRAGMENT_SHADER, fragment}},
                             .defines = std::move(defines),
                             .label = label})),
      mVao(label), mState(state) {}

void FullscreenPass::execute(const Framebuffer& target, int width, int height,
                             const ScissorRect* scissor) const {
    PipelineState state = mState;
    if (scissor) {
        state.scissor = true;
        state.scissorRect = *scissor;
    }
    applyState(state);
    glBindFramebuffer(GL_FRAMEBUFFER, target.id());
    glViewport(0, 0, width, height);
    glUseProgram(mProgram.id());
    glBindVertexArray(mVao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

void FullscreenPass::execute(const Framebuffer& target, int width, int height,
                             const PipelineState& state,
                             const std::function<void()>& setUniforms,
                             GLsizei vertices) const {
    applyState(state);
    glBindFramebuffer(GL_FRAMEBUFFER, target.id());
    glViewport(0, 0, width, height);
    glUseProgram(mProgram.id());
    if (setUniforms) setUniforms();
    glBindVertexArray(mVao.id());
    glDrawArrays(GL_TRIANGLES, 0, vertices);
}

} // namespace gpu
