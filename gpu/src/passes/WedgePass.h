// Penumbra wedges on the GPU, from the frame's directed silhouette edges (CasterSet):
// - setup(): a compute pass builds every wedge of a range of edges (conservative hull, kind,
//   frustum culling by group; shaders/wedge-setup.comp) into a GPU-only buffer;
// - draw(): one draw of 24 pulled vertices per wedge (shaders/wedge.vert), back faces only and
//   no depth test, so that every pixel is processed once per wedge, camera inside a wedge or
//   not; the fragment shader (shaders/wedge.frag) subtracts the edge's signed coverage from V;
// - resolve(): V = clamp(V, 0, 1), counting the pixels the clamp touched.
#pragma once

#include <gpu/ShaderLoader.h>
#include <gpu/State.h>

#include "../CasterSet.h"
#include "../Targets.h"

#include <array>
#include <cstdint>
#include <span>

namespace gpu {

struct WedgeCounts {
    std::uint32_t bounded = 0, fullscreen = 0, degenerate = 0, culled = 0;
    std::uint32_t clampedPixels = 0;
    std::uint64_t fragments = 0; // fragments that passed the hull test with non-zero coverage
};

class WedgePass {
public:
    // Back faces only (front faces culled): the hull's exit point along each eye ray. The
    // depth test keeps exits at or behind the G-buffer surface (reversed Z: LEQUAL), pushed
    // slightly farther by the polygon offset (conservative): where the whole hull lies in front
    // of the surface, P cannot be inside it. The fragment shader decides the rest from P itself.
    // V - coverage by reverse subtraction (dst - src) into the float visibility target;
    // depth clamp so that hull faces at infinity and before the near plane still rasterise.
    static constexpr PipelineState kState{
        .depthTest = true,
        .depthFunc = GL_LEQUAL,
        .depthWrite = false,
        .colorWrite = true,
        .cull = true,
        .cullFace = GL_FRONT,
        .blend = true,
        .blendSrc = GL_ONE,
        .blendDst = GL_ONE,
        .blendEquation = GL_FUNC_REVERSE_SUBTRACT,
        .polygonOffset = true,
        .polygonOffsetFactor = -1.0f, // reversed Z: negative = farther
        .polygonOffsetUnits = -4.0f,
        .depthClamp = true,
    };

    explicit WedgePass(const ShaderLoader& shaders);

    // Once per frame before setup(): sizes the wedge buffer for `edgeCount` edges, zeroes the
    // counters, binds both.
    void beginFrame(std::uint32_t edgeCount);
    void setup(std::span<const CasterRange> runs);
    void draw(const Targets& t, std::span<const CasterRange> runs);
    void resolve(const Targets& t);
    // Reads the counters back (waits for the GPU).
    WedgeCounts counts();

private:
    Program mSetup, mDraw, mResolve;
    VertexArray mVao;
    Buffer mWedges, mStats;
    std::size_t mWedgeCapacity = 0;
    Query mSamples;
    bool mSampled = false; // mSamples holds this frame's draw
};

} // namespace gpu
