// The shadow casters of a scene on the GPU, and their per-frame silhouettes.
// - Built once: welded topology per caster (geometry::Topology), its SilhouetteExtractor, and
//   static GPU buffers of every caster's welded positions and triangle indices, concatenated and
//   rebased to one global numbering (caps and wedges are drawn from them by vertex pulling).
// - Per frame: the extractors run from the light centre (reused while the light is still), and
//   their cap triangles, directed silhouette edges and groups go up in ONE upload (the buffer is
//   invalidated and refilled: orphaning), each caster's ids rebased once on the way.
#pragma once

#include <geometry/scene/Scene.h>
#include <geometry/shadow/Silhouette.h>
#include <geometry/shadow/Topology.h>
#include <gpu/gl/Objects.h>

#include <cstdint>
#include <span>
#include <vector>

namespace gpu {

// One caster's share of the frame upload (element indices into the arrays of Bindings.h).
struct CasterRange {
    std::uint32_t firstTriangle = 0, triangleCount = 0; // capTriangles[]
    std::uint32_t firstEdge = 0, edgeCount = 0;         // edges[]
    std::uint32_t firstGroup = 0, groupCount = 0;       // groups[]
};

// Element ranges of the frame's cap triangles and directed edges that one pass draws together
// (glMultiDrawArrays: one sub-draw per range; passes scale them by their vertices per element).
struct DrawSet {
    std::vector<GLint> triangleFirst;
    std::vector<GLsizei> triangleCount;
    std::vector<GLint> edgeFirst;
    std::vector<GLsizei> edgeCount;

    void add(std::uint32_t firstTriangle, std::uint32_t triangles, std::uint32_t firstEdge,
             std::uint32_t edges) {
        if (triangles > 0) {
            triangleFirst.push_back(static_cast<GLint>(firstTriangle));
            triangleCount.push_back(static_cast<GLsizei>(triangles));
        }
        if (edges > 0) {
            edgeFirst.push_back(static_cast<GLint>(firstEdge));
            edgeCount.push_back(static_cast<GLsizei>(edges));
        }
    }
    void add(const CasterRange& r) { add(r.firstTriangle, r.triangleCount, r.firstEdge, r.edgeCount); }
    void clear() {
        triangleFirst.clear();
        triangleCount.clear();
        edgeFirst.clear();
        edgeCount.clear();
    }
};

// GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT (at least 16), and x rounded up to a multiple of a:
// where the ranges of a per-frame upload start (CasterSet, PotentialSet).
std::size_t storageAlignment();
inline std::size_t alignUp(std::size_t x, std::size_t a) { return (x + a - 1) / a * a; }

// glMultiDrawArrays of `firsts`/`counts` elements of `perElement` vertices each (scratch:
// reused vectors).
void multiDrawElements(GLenum mode, std::span<const GLint> firsts, std::span<const GLsizei> counts,
                       int perElement, std::vector<GLint>& firstScratch,
                       std::vector<GLsizei>& countScratch);

class CasterSet {
public:
    // Objects whose method is not None, in scene order. Needs a current GL context.
    explicit CasterSet(const geometry::Scene& scene);

    std::size_t size() const { return mTopologies.size(); }
    const geometry::Topology& topology(std::size_t i) const { return mTopologies[i]; }
    std::size_t sceneObject(std::size_t i) const { return mObjectIndex[i]; }

    // Silhouettes of every caster from the light centre (classification, groups, directed edges,
    // caps by reference, influence bounds; no CPU volumes or wedges), then the upload.
    void update(const geometry::RectLight& light, const geometry::Aabb& sceneBounds);

    const geometry::SilhouetteFrame& frame(std::size_t i) const;
    // Caster i's first welded vertex and triangle in the static buffers' global numbering.
    std::uint32_t vertexBase(std::size_t i) const { return mVertexBase[i]; }
    std::uint32_t triangleBase(std::size_t i) const { return mTriangleBase[i]; }
    const CasterRange& range(std::size_t i) const { return mRanges[i]; }
    // Totals over all casters (the frame upload).
    std::uint32_t triangleCount() const { return mTotal.triangleCount; }
    std::uint32_t edgeCount() const { return mTotal.edgeCount; }
    std::uint32_t groupCount() const { return mTotal.groupCount; }
    std::size_t uploadBytes() const { return mUploadBytes; }
    // The scene bounds of the last update().
    const geometry::Aabb& sceneBounds() const { return mSceneBounds; }

    // Binds the static and per-frame arrays to their storage-buffer slots (Bindings.h).
    void bind() const;

private:
    std::vector<geometry::Topology> mTopologies;
    std::vector<std::size_t> mObjectIndex;
    std::vector<geometry::SilhouetteExtractor> mExtractors;
    std::vector<std::uint32_t> mVertexBase, mTriangleBase;
    Buffer mPositions, mIndices; // static
    Buffer mFrameData;           // per frame: capTriangles | edges | groups
    std::vector<std::byte> mStaging;
    std::size_t mEdgeOffset = 0, mGroupOffset = 0, mUploadBytes = 0; // bytes into mFrameData
    std::vector<CasterRange> mRanges;
    CasterRange mTotal;
    geometry::Aabb mSceneBounds;
};

} // namespace gpu
