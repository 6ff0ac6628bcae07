// Fixed-function state as data: one constexpr PipelineState per pass, applied from a known
// baseline by applyState(), so that no pass depends on what the previous one left enabled.
#pragma once

#include <epoxy/gl.h>

namespace gpu {

struct StencilFace {
    GLenum func = GL_ALWAYS;
    GLint ref = 0;
    GLuint readMask = 0xFF;
    GLenum stencilFail = GL_KEEP;
    GLenum depthFail = GL_KEEP;
    GLenum depthPass = GL_KEEP;
};

struct PipelineState {
    bool depthTest = false;
    GLenum depthFunc = GL_GREATER; // reversed Z (depth 1 = near, 0 = infinity)
    bool depthWrite = false;
    bool colorWrite = true;
    bool stencilTest = false;
    GLuint stencilWriteMask = 0xFF;
    StencilFace stencilFront;
    StencilFace stencilBack;
    bool cull = false;
    GLenum cullFace = GL_BACK;
    bool blend = false;
    GLenum blendSrc = GL_ONE;
    GLenum blendDst = GL_ZERO;
    GLenum blendEquation = GL_FUNC_ADD;
    bool polygonOffset = false;
    float polygonOffsetFactor = 0.0f;
    float polygonOffsetUnits = 0.0f;
    bool depthClamp = false;
    bool scissor = false;
};

// Applies every field (the full state, not a diff).
void applyState(const PipelineState& state);

} // namespace gpu
