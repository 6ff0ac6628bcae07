// One triangle over the viewport with a fragment shader, a fixed state and a target; the
// building block of the accumulate, resolve and shade passes.
#pragma once

#include <gpu/gl/ShaderLoader.h>
#include <gpu/gl/State.h>

#include <functional>

namespace gpu {

class FullscreenPass {
public:
    FullscreenPass(const ShaderLoader& shaders, const char* fragment, const char* label,
                   const PipelineState& state, std::vector<std::string> defines = {});
    // Optionally scissored to `scissor` (the pass's own state otherwise).
    void execute(const Framebuffer& target, int width, int height,
                 const ScissorRect* scissor = nullptr) const;
    // With a state of the caller's (e.g. a stencil function chosen per draw) and a hook that
    // sets uniforms once the program is bound.
    void execute(const Framebuffer& target, int width, int height, const PipelineState& state,
                 const std::function<void()>& setUniforms) const;

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
        : mPass(shaders, "accumulate.frag", "accumulate", kState) {}
    void execute(const Framebuffer& target, int width, int height,
                 const ScissorRect* scissor = nullptr) const {
        mPass.execute(target, width, height, scissor);
    }

private:
    FullscreenPass mPass;
};

} // namespace gpu
