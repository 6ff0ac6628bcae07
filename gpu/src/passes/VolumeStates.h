// Fixed-function state of the z-fail stencil volume passes (STYLE.md: state is data).
#pragma once

#include <gpu/gl/State.h>

namespace gpu {

// z-fail (Carmack): count volume faces *behind* the visible surface, +1 for back faces (the eye
// ray leaves a volume there) and -1 for front faces; the camera may sit inside a volume.
// Wrapping ops: counts may go negative transiently; only the final zero/non-zero matters.
// The count lives in the low 7 bits (mod 128: the write mask keeps the wrap there); bit 7 is the
// per-silhouette methods' mark of the pixels their wedges touched (GroupBatches.h).
inline constexpr GLuint kStencilCountMask = 0x7F;
inline constexpr GLuint kStencilWedgeMark = 0x80;

inline constexpr PipelineState kVolumeState{
    .depthTest = true,
    .depthFunc = GL_GREATER,
    .depthWrite = false,
    .colorWrite = false,
    .stencilTest = true,
    .stencilWriteMask = kStencilCountMask,
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
inline constexpr PipelineState kVolumeCapState = [] {
    PipelineState s = kVolumeState;
    s.polygonOffset = true;
    s.polygonOffsetFactor = -1.0f; // reversed Z: negative = farther
    s.polygonOffsetUnits = -4.0f;
    return s;
}();

} // namespace gpu
