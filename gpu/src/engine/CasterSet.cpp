// Casters on the GPU and their per-frame silhouettes (CasterSet.h).
#include "engine/CasterSet.h"

#include "engine/ShaderBindings.h"

#include <algorithm>
#include <cstring>

namespace gpu {

std::size_t storageAlignment() {
    GLint a = 0;
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &a);
    return static_cast<std::size_t>(std::max(a, 16));
}

void multiDrawElements(GLenum mode, std::span<const GLint> firsts, std::span<const GLsizei> counts,
                       int perElement, std::vector<GLint>& firstScratch,
                       std::vector<GLsizei>& countScratch) {
    if (firsts.empty()) return;
    firstScratch.resize(firsts.size());
    countScratch.resize(counts.size());
    for (std::size_t i = 0; i < firsts.size(); ++i) {
        // gl_VertexID starts at `first`: the shaders index the frame's arrays with it.
        firstScratch[i] = perElement * firsts[i];
        countScratch[i] = perElement * counts[i];
    }
    glMultiDrawArrays(mode, firstScratch.data(), countScratch.data(),
                      static_cast<GLsizei>(firsts.size()));
}

CasterSet::CasterSet(const geometry::Scene& scene) {
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        if (scene.objects[i].method == geometry::ShadowMethod::None) continue;
        mTopologies.emplace_back(scene.objects[i].mesh);
        mObjectIndex.push_back(i);
    }
    mExtractors.reserve(mTopologies.size());
    for (const auto& t : mTopologies) mExtractors.emplace_back(t);

    // Static welded geometry, rebased to one global numbering.
    std::vector<glm::vec4> positions;
    std::vector<std::uint32_t> indices;
    for (const auto& t : mTopologies) {
        const auto base = static_cast<std::uint32_t>(positions.size());
        mVertexBase.push_back(base);
        mTriangleBase.push_back(static_cast<std::uint32_t>(indices.size() / 3));
        for (const glm::vec3& p : t.positions()) positions.emplace_back(p, 1.0f);
        for (const glm::uvec3& tri : t.triangles())
            for (int k = 0; k < 3; ++k) indices.push_back(base + tri[k]);
    }
    if (positions.empty()) positions.emplace_back(0.0f); // storage cannot be empty
    if (indices.empty()) indices.push_back(0);
    mPositions = Buffer({.size = positions.size() * sizeof(glm::vec4), .data = positions.data(),
                         .flags = 0, .label = "welded-positions"});
    mIndices = Buffer({.size = indices.size() * sizeof(std::uint32_t), .data = indices.data(),
                       .flags = 0, .label = "welded-indices"});
    mFrameData = Buffer({.label = "silhouette-frame"});
    mRanges.resize(mTopologies.size());
}

const geometry::SilhouetteFrame& CasterSet::frame(std::size_t i) const {
    return mExtractors[i].frame();
}

void CasterSet::update(const geometry::RectLight& light, const geometry::Aabb& sceneBounds) {
    // The GPU extrudes sides and builds wedges from the directed edges and draws caps from the
    // triangle ids: the CPU builds no volumes, wedges or loops, and bounds groups cheaply.
    static const geometry::SilhouetteSettings settings = geometry::SilhouetteSettings::lean();
    bool changed = false;
    mSceneBounds = sceneBounds;
    mTotal = {};
    for (std::size_t i = 0; i < mExtractors.size(); ++i) {
        const geometry::SilhouetteFrame& f = mExtractors[i].update(light, sceneBounds, settings);
        changed |= !mExtractors[i].reused();
        CasterRange& r = mRanges[i];
        r.firstTriangle = mTotal.triangleCount;
        r.triangleCount = static_cast<std::uint32_t>(f.triangles.size());
        r.firstEdge = mTotal.edgeCount;
        r.edgeCount = static_cast<std::uint32_t>(f.edges.size());
        r.firstGroup = mTotal.groupCount;
        r.groupCount = static_cast<std::uint32_t>(f.groups.size());
        mTotal.triangleCount += r.triangleCount;
        mTotal.edgeCount += r.edgeCount;
        mTotal.groupCount += r.groupCount;
    }
    if (!changed && mUploadBytes > 0) return; // the light is still: last frame's upload stands

    // One staging block: capTriangles | edges | groups, each range aligned for binding.
    const std::size_t align = storageAlignment();
    mEdgeOffset = alignUp(std::max<std::size_t>(mTotal.triangleCount, 1) * sizeof(std::uint32_t),
                          align);
    mGroupOffset = alignUp(mEdgeOffset + std::max<std::size_t>(mTotal.edgeCount, 1) *
                                             sizeof(shader::GpuEdge),
                           align);
    mUploadBytes = mGroupOffset + std::max<std::size_t>(mTotal.groupCount, 1) *
                                      sizeof(shader::GpuGroup);
    mStaging.resize(mUploadBytes);
    auto* tris = reinterpret_cast<std::uint32_t*>(mStaging.data());
    auto* edges = reinterpret_cast<shader::GpuEdge*>(mStaging.data() + mEdgeOffset);
    auto* groups = reinterpret_cast<shader::GpuGroup*>(mStaging.data() + mGroupOffset);
    for (std::size_t i = 0; i < mExtractors.size(); ++i) {
        const geometry::SilhouetteFrame& f = mExtractors[i].frame();
        const CasterRange& r = mRanges[i];
        // Rebase once: caster-local ids to the global numbering of the static buffers.
        const std::uint32_t tb = mTriangleBase[i], vb = mVertexBase[i];
        for (std::size_t k = 0; k < f.triangles.size(); ++k) {
            const std::uint32_t t = f.triangles[k];
            tris[r.firstTriangle + k] = (t & geometry::kTriangleFlipped) |
                                        ((t & ~geometry::kTriangleFlipped) + tb);
        }
        for (std::uint32_t g = 0; g < r.groupCount; ++g) {
            const geometry::SilhouetteGroup& sg = f.groups[g];
            const std::uint32_t global = r.firstGroup + g;
            groups[global] = shader::GpuGroup{
                .influenceMin = glm::vec4(sg.influenceBounds.min, 0.0f),
                .influenceMax = glm::vec4(sg.influenceBounds.max, 0.0f),
                .firstEdge = r.firstEdge + sg.firstEdge,
                .edgeCount = sg.edgeCount,
                .firstTriangle = r.firstTriangle + sg.firstTriangle,
                .triangleCount = sg.triangleCount};
            for (std::uint32_t k = sg.firstEdge; k < sg.firstEdge + sg.edgeCount; ++k)
                edges[r.firstEdge + k] = shader::GpuEdge{f.edges[k].v0 + vb, f.edges[k].v1 + vb,
                                                         global, 0u};
        }
    }
    if (mFrameData.size() >= mUploadBytes && mFrameData.id() != 0)
        glInvalidateBufferData(mFrameData.id()); // orphan: the driver may hand us fresh storage
    mFrameData.uploadResize(mStaging.data(), mUploadBytes);
}

void CasterSet::bind() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_WELDED_POSITIONS, mPositions.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_WELDED_INDICES, mIndices.id());
    if (mUploadBytes == 0) return;
    const GLuint id = mFrameData.id();
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BINDING_CAP_TRIANGLES, id, 0,
                      static_cast<GLsizeiptr>(mEdgeOffset));
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BINDING_EDGES, id,
                      static_cast<GLintptr>(mEdgeOffset),
                      static_cast<GLsizeiptr>(mGroupOffset - mEdgeOffset));
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BINDING_GROUPS, id,
                      static_cast<GLintptr>(mGroupOffset),
                      static_cast<GLsizeiptr>(mUploadBytes - mGroupOffset));
}

} // namespace gpu
