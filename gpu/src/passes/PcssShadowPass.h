// PCSS, shadow pass: the casters from the light's centre into one face's shadow map (a layer of
// a depth-array texture), with geometry::PcssFrame::projection in PcssUniforms::shadowProj.
// - Depth only, zNear / z, reversed: cleared to 0 (nothing), GREATER keeps the nearest surface.
// - No culling: every triangle occludes from both sides (open meshes, cards, level geometry).
// - Alpha-tested materials cut their texels out (lib/Material.glsl), as in the G-buffer.
#pragma once

#include <gpu/gl/ShaderLoader.h>
#include <gpu/gl/State.h>

#include "engine/SceneGeometry.h"

#include <cstddef>
#include <span>

namespace gpu {

class PcssShadowPass {
public:
    static constexpr PipelineState kState{
        .depthTest = true,
        .depthFunc = GL_GREATER, // reversed: 1 at zNear, 0 infinitely far
        .depthWrite = true,
        .colorWrite = false,
    };

    explicit PcssShadowPass(const ShaderLoader& shaders);
    // Clears `target` (a depth-only framebuffer of one face's layer) and draws the objects into
    // it; PcssUniforms must be bound.
    void execute(const Framebuffer& target, int face, int resolution, const SceneGeometry& geometry,
                 std::span<const std::size_t> objects) const;

private:
    Program mOpaque, mAlphaTested;
};

} // namespace gpu
