#include "StencilVolumePass.h"

#include "VolumeStates.h"

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
    glBindFramebuffer(GL_FRAMEBUFFER, t.visibilityFbo.id());
    glViewport(0, 0, t.width, t.height);
    glBindVertexArray(mEmptyVao.id());
    // gl_VertexID starts at `first`: the ranges index the frame's arrays directly.
    const auto tri0 = static_cast<GLint>(3 * range.firstTriangle);
    const auto triN = static_cast<GLsizei>(3 * range.triangleCount);
    if (triN > 0) {
        applyState(kVolumeCapState);
        glUseProgram(mFrontCaps.id());
        glDrawArrays(GL_TRIANGLES, tri0, triN);
        applyState(kVolumeState);
        glUseProgram(mBackCaps.id());
        glDrawArrays(GL_TRIANGLES, tri0, triN);
    }
    if (range.edgeCount > 0) {
        applyState(kVolumeState);
        glUseProgram(mSides.id());
        glDrawArrays(GL_TRIANGLES, static_cast<GLint>(6 * range.firstEdge),
                     static_cast<GLsizei>(6 * range.edgeCount));
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
