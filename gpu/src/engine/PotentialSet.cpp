// The frame arrays of wedges-bitmask silhouettes=potential (PotentialSet.h).
#include "engine/PotentialSet.h"

#include "engine/ShaderBindings.h"

#include <algorithm>
#include <stdexcept>

namespace gpu {

namespace {

constexpr geometry::SilhouetteSettings twoSidedLean() {
    geometry::SilhouetteSettings s = geometry::SilhouetteSettings::lean();
    s.oneSidedClosed = false;    // D(p, c) two-sided for every mesh
    s.flatTrianglesFace = false; // a triangle whose plane holds the centre: no volume
    return s;
}

} // namespace

void PotentialSet::update(const CasterSet& casters, std::span<const std::uint32_t> subset,
                          const geometry::RectLight& light) {
    const bool sameSubset = std::equal(subset.begin(), subset.end(), mSubset.begin(), mSubset.end());
    if (mHasLight && sameSubset && light == mLight && mBytes > 0) return;
    if (!sameSubset) {
        mCasters.clear();
        mSubset.assign(subset.begin(), subset.end());
        for (std::uint32_t c : subset) {
            Caster k;
            k.index = c;
            k.extractor = std::make_unique<geometry::SilhouetteExtractor>(casters.topology(c));
            k.potential = std::make_unique<geometry::PotentialSilhouettes>(casters.topology(c));
            for (const glm::vec3& x : casters.topology(c).positions()) k.bounds.extend(x);
            mCasters.push_back(std::move(k));
        }
    }
    mHasLight = true;
    mLight = light;
    static constexpr geometry::SilhouetteSettings settings = twoSidedLean();
    const geometry::Aabb& sceneBounds = casters.sceneBounds();

    // Sizes first.
    std::uint32_t triangles = 0, sides = 0, potential = 0, groups = 0;
    mStats = {};
    mFlatTriangles = 0;
    for (Caster& k : mCasters) {
        const geometry::SilhouetteFrame& f = k.extractor->update(light, sceneBounds, settings);
        const geometry::PotentialEdgeStats s = k.potential->update(light, k.edges);
        mStats.interior += s.interior;
        mStats.boundary += s.boundary;
        mStats.nonManifold += s.nonManifold;
        mStats.skipped += s.skipped;
        mFlatTriangles += f.flatTriangles;
        triangles += static_cast<std::uint32_t>(f.triangles.size());
        sides += static_cast<std::uint32_t>(f.edges.size());
        potential += static_cast<std::uint32_t>(k.edges.size());
        groups += static_cast<std::uint32_t>(f.groups.size()) + 1;
    }
    mCentreEdges = sides;
    mWedgeTotal = potential;
    mEdgeTotal = sides + potential;

    const std::size_t align = storageAlignment();
    mEdgeOffset = alignUp(std::max<std::uint32_t>(triangles, 1) * sizeof(std::uint32_t), align);
    mApexOffset = alignUp(mEdgeOffset + std::max<std::uint32_t>(mEdgeTotal, 1) *
                                            sizeof(shader::GpuEdge), align);
    mGroupOffset = alignUp(mApexOffset + std::max<std::uint32_t>(mEdgeTotal, 1) *
                                             sizeof(glm::uvec2), align);
    mBytes = mGroupOffset + std::max<std::uint32_t>(groups, 1) * sizeof(shader::GpuGroup);
    mStaging.assign(mBytes, std::byte{0});
    auto* tris = reinterpret_cast<std::uint32_t*>(mStaging.data());
    auto* edges = reinterpret_cast<shader::GpuEdge*>(mStaging.data() + mEdgeOffset);
    auto* apexes = reinterpret_cast<glm::uvec2*>(mStaging.data() + mApexOffset);
    auto* gpuGroups = reinterpret_cast<shader::GpuGroup*>(mStaging.data() + mGroupOffset);
    std::fill(apexes, apexes + mEdgeTotal, glm::uvec2(geometry::kNoApex));

    mVolumes.clear();
    mWedges.clear();
    mWedgeRuns.clear();
    mEdgeA.clear();
    mEdgeB.clear();
    std::uint32_t tri = 0, side = 0, pot = sides, group = 0;
    for (Caster& k : mCasters) {
        const geometry::SilhouetteFrame& f = k.extractor->frame();
        const std::uint32_t vb = casters.vertexBase(k.index), tb = casters.triangleBase(k.index);
        const std::uint32_t firstTri = tri, firstSide = side;
        for (const std::uint32_t t : f.triangles)
            tris[tri++] = (t & geometry::kTriangleFlipped) | ((t & ~geometry::kTriangleFlipped) + tb);
        for (const geometry::SilhouetteGroup& g : f.groups) {
            gpuGroups[group] = shader::GpuGroup{
                .influenceMin = glm::vec4(g.influenceBounds.min, 0.0f),
                .influenceMax = glm::vec4(g.influenceBounds.max, 0.0f),
                .firstEdge = firstSide + g.firstEdge,
                .edgeCount = g.edgeCount,
                .firstTriangle = firstTri + g.firstTriangle,
                .triangleCount = g.triangleCount};
            for (std::uint32_t e = g.firstEdge; e < g.firstEdge + g.edgeCount; ++e)
                edges[side++] = shader::GpuEdge{f.edges[e].v0 + vb, f.edges[e].v1 + vb, group, 0u};
            ++group;
        }
        // The caster's potential edges under one group: the caster's whole box. (Not the union
        // of the centre's groups: a triangle whose plane holds the light's centre is in none, and
        // a wall through the centre lost its wedges with it.)
        const geometry::Aabb influence =
            geometry::occluderInfluenceBounds(k.bounds, light, sceneBounds);
        const std::uint32_t firstPot = pot;
        const auto positions = casters.topology(k.index).positions();
        for (const geometry::PotentialEdge& e : k.edges) {
            mEdgeA.push_back(positions[e.v0]);
            mEdgeB.push_back(positions[e.v1]);
            edges[pot] = shader::GpuEdge{e.v0 + vb, e.v1 + vb, group, 0u};
            apexes[pot] = glm::uvec2(e.apex[0] == geometry::kNoApex ? geometry::kNoApex : e.apex[0] + vb,
                                     e.apex[1] == geometry::kNoApex ? geometry::kNoApex : e.apex[1] + vb);
            ++pot;
        }
        gpuGroups[group] = shader::GpuGroup{.influenceMin = glm::vec4(influence.min, 0.0f),
                                            .influenceMax = glm::vec4(influence.max, 0.0f),
                                            .firstEdge = firstPot,
                                            .edgeCount = pot - firstPot,
                                            .firstTriangle = firstTri,
                                            .triangleCount = tri - firstTri};
        ++group;
        mVolumes.add(firstTri, tri - firstTri, firstSide, side - firstSide);
        mWedges.add(0, 0, firstPot, pot - firstPot);
        if (pot > firstPot) mWedgeRuns.push_back(CasterRange{.firstEdge = firstPot, .edgeCount = pot - firstPot});
    }
    // The twin slots (a second silhouette cone: wedge-setup.comp), twinOffset() past each edge.
    const std::size_t runs = mWedges.edgeFirst.size();
    for (std::size_t r = 0; r < runs; ++r)
        mWedges.add(0, 0, static_cast<std::uint32_t>(mWedges.edgeFirst[r]) + mWedgeTotal,
                    static_cast<std::uint32_t>(mWedges.edgeCount[r]));
    if (mData.size() >= mBytes && mData.id() != 0) glInvalidateBufferData(mData.id());
    mData.uploadResize(mStaging.data(), mBytes);
}

void PotentialSet::keptWedges(std::span<const std::uint8_t> keep, DrawSet& wedges,
                              std::vector<CasterRange>& runs) const {
    if (keep.size() != mWedgeTotal) throw std::logic_error("PotentialSet::keptWedges: wrong size");
    wedges.clear();
    runs.clear();
    // Runs of kept edges within each caster's run (a set-up run has one group).
    for (const CasterRange& r : mWedgeRuns) {
        const std::uint32_t base = mCentreEdges;
        std::uint32_t start = 0, length = 0;
        for (std::uint32_t e = r.firstEdge; e < r.firstEdge + r.edgeCount; ++e) {
            const bool kept = keep[e - base] != 0;
            if (kept) {
                if (length == 0) start = e;
                ++length;
            }
            if (length > 0 && (!kept || e + 1 == r.firstEdge + r.edgeCount)) {
                runs.push_back(CasterRange{.firstEdge = start, .edgeCount = length});
                length = 0;
            }
        }
    }
    for (const CasterRange& r : runs) wedges.add(0, 0, r.firstEdge, r.edgeCount);
    for (const CasterRange& r : runs) wedges.add(0, 0, r.firstEdge + mWedgeTotal, r.edgeCount);
}

void PotentialSet::bind(const CasterSet& casters) const {
    casters.bind(); // the static welded geometry (and the centre's arrays, rebound below)
    const GLuint id = mData.id();
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BINDING_CAP_TRIANGLES, id, 0,
                      static_cast<GLsizeiptr>(mEdgeOffset));
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BINDING_EDGES, id,
                      static_cast<GLintptr>(mEdgeOffset),
                      static_cast<GLsizeiptr>(mApexOffset - mEdgeOffset));
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BINDING_EDGE_APEXES, id,
                      static_cast<GLintptr>(mApexOffset),
                      static_cast<GLsizeiptr>(mGroupOffset - mApexOffset));
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BINDING_GROUPS, id,
                      static_cast<GLintptr>(mGroupOffset),
                      static_cast<GLsizeiptr>(mBytes - mGroupOffset));
}

} // namespace gpu
