// Fixed-function state as data: one constexpr PipelineState per pass, applied from a known
// baseline by applyState(), so that no pass depends on what the previous one left enabled.
#pragma once

#include <epoxy/gl.h>

#include <array>

namespace gpu {

struct StencilFace {
    GLenum func = GL_ALWAYS;
    GLint ref = 0;
    GLuint readMask = 0xFF;
    GLenum stencilFail = GL_KEEP;
    GLenum depthFail = GL_KEEP;
    GLenum depthPass = GL_KEEP;
};

// Blend and colour-write state of one colour attachment (used when
// PipelineState::independentTargets is set; otherwise the shared fields apply to every target).
struct ColorTargetState {
    bool blend = false;
    GLenum blendSrc = GL_ONE;
    GLenum blendDst = GL_ZERO;
    GLenum blendEquation = GL_FUNC_ADD;
    bool writeR = true, writeG = true, writeB = true, writeA = true;
};

inline constexpr int kMaxColorTargets = 8;

// Window-space rectangle (pixels, lower-left origin), used when PipelineState::scissor is set.
struct ScissorRect {
    GLint x = 0, y = 0;
    GLsizei width = 0, height = 0;
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
    // GL_LINE: polygons as their edges (debug wireframes); the polygon offset applies then too.
    GLenum polygonMode = GL_FILL;
    bool scissor = false;
    ScissorRect scissorRect; // set at draw time by passes that scissor (e.g. per group)
    // Per-attachment blend and colour masks (MRT passes that treat targets differently).
    bool independentTargets = false;
    std::array<ColorTargetState, kMaxColorTargets> targets{};
    // Fixed-function logic op on integer colour targets (dst = src op dst; blending does not
    // apply to them): wedges-bitmask's XOR of a wedge's light-sample mask into its group's, OR
    // of the groups' masks into the final one.
    bool logicOp = false;
    GLenum logicOpMode = GL_COPY;
};

// Applies every field (the full state, not a diff).
void applyState(const PipelineState& state);

} // namespace gpu
