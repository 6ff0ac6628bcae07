#include "GBufferPass.h"

#include <cstddef>
#include <vector>

namespace gpu {

namespace {

struct SceneVertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec3 albedo;
};

// Vertices expanded per triangle (flat normals, per-triangle material colour).
std::vector<SceneVertex> expandSceneVertices(const geometry::Scene& scene) {
    std::vector<SceneVertex> out;
    out.reserve(3 * scene.triangleCount());
    for (const auto& object : scene.objects) {
        const auto& mesh = object.mesh;
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            const glm::uvec3 tri = mesh.triangles[t];
            const glm::vec3 a = mesh.positions[tri.x], b = mesh.positions[tri.y],
                            c = mesh.positions[tri.z];
            const glm::vec3 n = glm::cross(b - a, c - a);
            const float len = glm::length(n);
            if (!(len > 0.0f)) continue; // zero area: rasterises nothing, has no normal
            glm::vec3 albedo(0.8f);
            if (!mesh.triangleMaterial.empty() && !mesh.materials.empty())
                albedo = glm::vec3(mesh.materials[mesh.triangleMaterial[t]].baseColor);
            for (const glm::vec3& p : {a, b, c}) out.push_back({p, n / len, albedo});
        }
    }
    return out;
}

} // namespace

GBufferPass::GBufferPass(const ShaderLoader& shaders, const geometry::Scene& scene)
    : mProgram(shaders.load({.stages = {{GL_VERTEX_SHADER, "gbuffer.vert"},
                                        {GL_FRAGMENT_SHADER, "gbuffer.frag"}},
                             .label = "gbuffer"})),
      mVao("scene") {
    const std::vector<SceneVertex> vertices = expandSceneVertices(scene);
    mVertices = Buffer({.size = vertices.size() * sizeof(SceneVertex), .data = vertices.empty() ? nullptr : vertices.data(),
                        .flags = 0, .label = "scene-vertices"});
    mCount = static_cast<GLsizei>(vertices.size());
    if (mCount > 0) mVao.vertexBuffer(0, mVertices, 0, sizeof(SceneVertex));
    mVao.attribute(0, 0, 3, GL_FLOAT, offsetof(SceneVertex, position));
    mVao.attribute(1, 0, 3, GL_FLOAT, offsetof(SceneVertex, normal));
    mVao.attribute(2, 0, 3, GL_FLOAT, offsetof(SceneVertex, albedo));
}

void GBufferPass::execute(const Targets& t) {
    applyState(kState);
    glBindFramebuffer(GL_FRAMEBUFFER, t.gbuffer.id());
    glViewport(0, 0, t.width, t.height);
    const float zero[4] = {0, 0, 0, 0};
    for (int i = 0; i < 3; ++i) glClearNamedFramebufferfv(t.gbuffer.id(), GL_COLOR, i, zero);
    glClearNamedFramebufferfi(t.gbuffer.id(), GL_DEPTH_STENCIL, 0, 0.0f, 0); // reversed Z
    if (mCount == 0) return;
    glUseProgram(mProgram.id());
    glBindVertexArray(mVao.id());
    glDrawArrays(GL_TRIANGLES, 0, mCount);
}

} // namespace gpu
