#include "passes/StencilVolumePass.h"

#include "passes/VolumeStates.h"

#include <glm/glm.hpp>

namespace gpu {

namespace {

Program loadPulled(const ShaderLoader& shaders, const char* variant, const char* label) {
    // volume.geom clamps each triangle's fragment depth to its own depth range (it explains
    // the edge-on slivers that otherwise miscount).
    ProgramDesc desc{.stages = {{GL_VERTEX_SHADER, "volume-pulled.vert"},
                                {GL_GEOMETRY_SHADER, "volume.geom"},
                                {GL_FRAGMENT_SHADER, "volume.frag"}},
                     .label = label};
    if (variant) desc.defines.push_back(variant);
    return shaders.load(desc);
}

} // namespace

StencilVolumePass::StencilVolumePass(const ShaderLoader& shaders)
    : mFrontCaps(loadPulled(shaders, "CAP_FRONT", "volume-front-caps")),
      mBackCaps(loadPulled(shaders, "CAP_BACK", "volume-back-caps")),
      mSides(loadPulled(shaders, nullptr, "volume-sides")),
      mVertices(shaders.load({.stages = {{GL_VERTEX_SHADER, "volume.vert"},
                                         {GL_GEOMETRY_SHADER, "volume.geom"},
                                         {GL_FRAGMENT_SHADER, "volume.frag"}},
                              .label = "shadow-volume"})),
      mEmptyVao("volume-pulled"), mVao("shadow-volume") {
    mVao.attribute(0, 0, 4, GL_FLOAT, 0);
}

void StencilVolumePass::drawCentre(const Targets& t, const CasterRange& range) {
    DrawSet set;
    set.add(range);
    drawCentre(t.visibilityFbo, t, set);
}

void StencilVolumePass::drawCentre(const Framebuffer& target, const Targets& t,
                                   const DrawSet& set, const ScissorRect* scissor) {
    PipelineState cap = kVolumeCapState, side = kVolumeState;
    if (scissor) {
        cap.scissor = side.scissor = true;
        cap.scissorRect = side.scissorRect = *scissor;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, target.id());
    glViewport(0, 0, t.width, t.height);
    glBindVertexArray(mEmptyVao.id());
    if (!set.triangleFirst.empty()) {
        applyState(cap);
        glUseProgram(mFrontCaps.id());
        multiDrawElements(GL_TRIANGLES, set.triangleFirst, set.triangleCount, 3, mFirsts, mCounts);
        applyState(side);
        glUseProgram(mBackCaps.id());
        multiDrawElements(GL_TRIANGLES, set.triangleFirst, set.triangleCount, 3, mFirsts, mCounts);
    }
    if (!set.edgeFirst.empty()) {
        applyState(side);
        glUseProgram(mSides.id());
        multiDrawElements(GL_TRIANGLES, set.edgeFirst, set.edgeCount, 6, mFirsts, mCounts);
    }
}

void StencilVolumePass::drawVertices(const Targets& t,
                                     const geometry::ShadowVolumeGeometry& volume,
                                     std::size_t frontCapVertices) {
    if (volume.vertices.empty()) return;
    mVertexBuffer.uploadResize(volume.vertices.data(), volume.vertices.size() * sizeof(glm::vec4));
    mVao.vertexBuffer(0, mVertexBuffer, 0, sizeof(glm::vec4));
    glBindFramebuffer(GL_FRAMEBUFFER, t.visibilityFbo.id());
    glViewport(0, 0, t.width, t.height);
    glUseProgram(mVertices.id());
    glBindVertexArray(mVao.id());
    applyState(kVolumeCapState);
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(frontCapVertices));
    applyState(kVolumeState);
    glDrawArrays(GL_TRIANGLES, static_cast<GLint>(frontCapVertices),
                 static_cast<GLsizei>(volume.vertices.size() - frontCapVertices));
}

} // namespace gpu
