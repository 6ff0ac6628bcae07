// One triangle over the viewport with a fragment shader, a fixed state and a target; the
// building block of the accumulate, resolve and shade passes.
#pragma once

#include <gpu/gl/ShaderLoader.h>
#include <gpu/gl/State.h>

#include <glm/glm.hpp>

#include <functional>

namespace gpu {

class FullscreenPass {
public:
    // `vertex`: fullscreen.vert, or a shader drawing the same triangle with more outputs.
    FullscreenPass(const ShaderLoader& shaders, const char* fragment, const char* label,
                   const PipelineState& state, std::vector<std::string> defines = {},
                   const char* vertex = "fullscreen.vert");
    // Optionally scissored to `scissor` (the pass's own state otherwise).
    void execute(const Framebuffer& target, int width, int height,
                 const ScissorRect* scissor = nullptr) const;
    // With a state of the caller's (e.g. a stencil function chosen per draw) and a hook that
    // sets uniforms once the program is bound; `vertices` for a vertex shader that draws more
    // than the one triangle (tile-rects.vert: 6 per rectangle).
    void execute(const Framebuffer& target, int width, int height, const PipelineState& state,
                 const std::function<void()>& setUniforms, GLsizei vertices = 3) const;

private:
    Program mProgram;
    VertexArray mVao;
    PipelineState mState;
};

// Adds frame.params.y into V where the stencil count is zero (lit).
class AccumulatePass {
public:
    static constexpr PipelineState kState{
        .stencilTest = true,
        .stencilWriteMask = 0,
        .stencilFront = {.func = GL_EQUAL, .ref = 0},
        .stencilBack = {.func = GL_EQUAL, .ref = 0},
        .blend = true,
        .blendSrc = GL_ONE,
        .blendDst = GL_ONE,
    };
    explicit AccumulatePass(const ShaderLoader& shaders)
        : mPass(shaders, "accumulate.frag", "accumulate", kState),
          mOwnPlane(shaders, "accumulate.frag", "accumulate-own-plane", kState, {"OWN_PLANE"}) {}
    void execute(const Framebuffer& target, int width, int height,
                 const ScissorRect* scissor = nullptr) const {
        mPass.execute(target, width, height, scissor);
    }
    // Also not where `lightPoint` lies behind the receiver's own plane (the G-buffer's position
    // and facet normal, which the caller binds): the reference's rule, as raytrace's.
    void executeFromPoint(const Framebuffer& target, int width, int height,
                          const glm::vec3& lightPoint) const {
        mOwnPlane.execute(target, width, height, kState, [&] {
            glUniform3f(0, lightPoint.x, lightPoint.y, lightPoint.z);
        });
    }

private:
    FullscreenPass mPass, mOwnPlane;
};

} // namespace gpu
