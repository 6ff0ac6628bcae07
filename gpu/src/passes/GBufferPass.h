// G-buffer pass: every object (casters and receivers alike) into world position, flat
// viewer-facing normal, albedo and reversed-Z depth + stencil.
#pragma once

#include <geometry/Scene.h>
#include <gpu/ShaderLoader.h>
#include <gpu/State.h>

#include "../Targets.h"

namespace gpu {

class GBufferPass {
public:
    static constexpr PipelineState kState{
        .depthTest = true,
        .depthFunc = GL_GREATER, // reversed Z
        .depthWrite = true,
    };

    GBufferPass(const ShaderLoader& shaders, const geometry::Scene& scene);
    void execute(const Targets& t);

private:
    Program mProgram;
    Buffer mVertices;
    VertexArray mVao;
    GLsizei mCount = 0;
};

} // namespace gpu
