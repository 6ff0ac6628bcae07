// G-buffer pass: every object (casters and receivers alike) into world position, flat
// viewer-facing normal, albedo and reversed-Z depth + stencil. Alpha-tested materials cut their
// texels out (lib/Material.glsl), so leaf cards are seen through where the leaves are not.
#pragma once

#include <gpu/gl/ShaderLoader.h>
#include <gpu/gl/State.h>

#include "engine/SceneGeometry.h"
#include "engine/Targets.h"

namespace gpu {

class GBufferPass {
public:
    static constexpr PipelineState kState{
        .depthTest = true,
        .depthFunc = GL_GREATER, // reversed Z
        .depthWrite = true,
    };

    explicit GBufferPass(const ShaderLoader& shaders);
    void execute(const Targets& t, const SceneGeometry& geometry);

private:
    Program mOpaque, mAlphaTested;
};

} // namespace gpu
