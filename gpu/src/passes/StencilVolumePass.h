// z-fail stencil counts of shadow volumes into the shared stencil buffer (Targets::depthStencil).
// Two sources of volume geometry:
// - drawCentre(): the light centre's volumes by vertex pulling (caps from the frame's cap
//   triangles, sides from its directed silhouette edges; shaders/volume-pulled.vert), for a
//   range of casters;
// - drawVertices(): CPU-built vertices of any light point (geometry/shadow/ShadowVolume.h), front caps
//   first (the reference's per-sample volumes).
#pragma once

#include <geometry/shadow/ShadowVolume.h>
#include <gpu/gl/ShaderLoader.h>
#include <gpu/gl/State.h>

#include "engine/CasterSet.h"
#include "engine/Targets.h"

namespace gpu {

class StencilVolumePass {
public:
    explicit StencilVolumePass(const ShaderLoader& shaders);

    // Caps and sides of a range of the frame's silhouette groups for the light centre
    // (CasterSet::bind() and the frame uniforms are the caller's).
    void drawCentre(const Targets& t, const CasterRange& range);
    // The same for any set of ranges (e.g. a batch of groups), into `target` (which must hold
    // the shared depth-stencil attachment), optionally scissored.
    void drawCentre(const Framebuffer& target, const Targets& t, const DrawSet& set,
                    const ScissorRect* scissor = nullptr);
    // `frontCapVertices` leading vertices of `volume` are front caps (drawn with the cap offset).
    void drawVertices(const Targets& t, const geometry::ShadowVolumeGeometry& volume,
                      std::size_t frontCapVertices);

private:
    Program mFrontCaps, mBackCaps, mSides, mVertices;
    VertexArray mEmptyVao, mVao;
    Buffer mVertexBuffer;
    std::vector<GLint> mFirsts;
    std::vector<GLsizei> mCounts;
};

} // namespace gpu
