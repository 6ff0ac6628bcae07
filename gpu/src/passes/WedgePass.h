// Penumbra wedges on the GPU, from the frame's directed silhouette edges (CasterSet):
// - setup(): a compute pass builds every wedge of a range of edges (conservative hull, kind,
//   frustum culling by group; shaders/wedge-setup.comp) into a GPU-only buffer;
// - draw(): 8 triangles per wedge over its 6 hull corners, pulled by index (shaders/wedge.vert;
//   6 vertex invocations per wedge rather than 24), in two draws: entry faces of
//   hulls the camera is outside of (depth GEQUAL against the surface), exit faces of the others
//   (LEQUAL), so that every pixel is processed once per wedge, camera inside a wedge or not;
//   the fragment shader (shaders/wedge.frag) subtracts the edge's signed coverage from V;
// - resolve(): V = clamp(V, 0, 1), counting the pixels the clamp touched.
#pragma once

#include <gpu/gl/ShaderLoader.h>
#include <gpu/gl/State.h>

#include "engine/CasterSet.h"
#include "engine/Targets.h"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace gpu {

struct WedgeCounts {
    std::uint32_t bounded = 0, fullscreen = 0, degenerate = 0, culled = 0;
    std::uint32_t eyeInside = 0; // bounded wedges drawn by their exit faces
    std::uint32_t clampedPixels = 0;
    // Output::BitmaskPotential: edges whose Fullscreen hull two silhouette cones replace (the
    // first counted by its kind, the second, in the twin slot, not counted by kind).
    std::uint32_t cones = 0;
    // GL_SAMPLES_PASSED over the wedge draws. The shader discards fragments without a surface,
    // outside the hull or with zero coverage; llvmpipe counts after the discard (then this is
    // the fragments with non-zero coverage), a driver may count at the early depth test instead.
    std::uint64_t fragments = 0;
};

class WedgePass {
public:
    // Entry draw (camera outside the hull): front faces, kept where the hull's entry is at or
    // in front of the G-buffer surface (reversed Z: GEQUAL), pulled slightly nearer by the
    // polygon offset (conservative). Exit draw (camera inside, and full-screen wedges): back
    // faces, kept where the exit is at or behind the surface (LEQUAL), pushed slightly farther.
    // Both: V - coverage by reverse subtraction (dst - src) into the float visibility target;
    // depth clamp so that hull faces at infinity and before the near plane still rasterise.
    static constexpr PipelineState kEntryState{
        .depthTest = true,
        .depthFunc = GL_GEQUAL,
        .depthWrite = false,
        .colorWrite = true,
        .cull = true,
        .cullFace = GL_BACK,
        .blend = true,
        .blendSrc = GL_ONE,
        .blendDst = GL_ONE,
        .blendEquation = GL_FUNC_REVERSE_SUBTRACT,
        .polygonOffset = true,
        .polygonOffsetFactor = 1.0f, // reversed Z: positive = nearer
        .polygonOffsetUnits = 4.0f,
        .depthClamp = true,
    };
    static constexpr PipelineState kExitState = [] {
        PipelineState s = kEntryState;
        s.depthFunc = GL_LEQUAL;
        s.cullFace = GL_FRONT;
        s.polygonOffsetFactor = -1.0f; // farther
        s.polygonOffsetUnits = -4.0f;
        return s;
    }();

    // What the wedge fragments write: V minus coverage into one float target (additive,
    // multiply), or per-part sums (targets 0-3, by ADD) and minima (4-7, by MIN) into up to 8
    // float targets (wedges-blend: shaders/wedge-parts.frag), or the light samples the edge's
    // region holds, XORed by the logic op into unsigned-integer targets (wedges-bitmask:
    // shaders/wedge-bitmask.frag).
    // BitmaskCounts: the same samples added, signed, to per-sample counts by image atomics
    // (wedges-bitmask combine=counts); no colour writes.
    // BitmaskPotential (wedges-bitmask silhouettes=potential): counts by image atomics as
    // BitmaskCounts, weighted by m_P(e), and m_P(e) times the edge's coverage added into one
    // float target by blending.
    enum class Output { Subtract, Parts4, Bitmask, BitmaskCounts, BitmaskPotential };

    // `defines`: the fragment program's variant (wedges-blend: shaders/wedge-parts.frag's).
    explicit WedgePass(const ShaderLoader& shaders, Output output = Output::Subtract,
                       std::vector<std::string> defines = {});
    // The wedge draw program, for a variant's own uniforms (set with glProgramUniform*).
    GLuint drawProgram() const { return mDraw.id(); }

    // Once per frame before setup(): sizes the wedge buffer for `edgeCount` wedges, zeroes the
    // counters, binds both.
    void beginFrame(std::uint32_t edgeCount);
    // The wedges of `runs`' edges. Output::BitmaskPotential: each edge's second silhouette cone
    // (wedge-setup.comp) goes to the slot `twinOffset` further on, which beginFrame must have
    // sized for and the draw set must hold.
    void setup(std::span<const CasterRange> runs, std::uint32_t twinOffset = 0);
    // Wedges of `set`'s edges into `target` (V there minus coverage; the target must hold the
    // shared depth-stencil attachment), optionally scissored. `markTouched`: every fragment that
    // passes the depth test also sets the stencil's kStencilWedgeMark bit (VolumeStates.h), for
    // the per-silhouette methods, which then combine only where a wedge reached (a superset of
    // the pixels with non-zero coverage: the mark happens at the early test, before the hull
    // test may discard).
    // `countFragments`: add the draw's samples to WedgeCounts::fragments (a GL_SAMPLES_PASSED
    // query: the caller must not have one active); off for a redraw of the same wedges.
    void draw(const Framebuffer& target, const Targets& t, const DrawSet& set,
              const ScissorRect* scissor = nullptr, bool markTouched = false,
              bool countFragments = true);
    // The hulls of `set`'s wedges as the two draws above place them (entry and exit faces,
    // full-screen triangles), with another program on wedge.vert (a debug view: its fragment
    // stage and `state`, e.g. line mode, are the caller's). No query, no counters.
    void drawHulls(const Framebuffer& target, const Targets& t, const DrawSet& set,
                   GLuint program, const PipelineState& state);
    void resolve(const Targets& t);
    // Binds this pass's wedge buffer at BINDING_WEDGES (for another reader: WedgeTilePass).
    void bindWedges() const;
    // Reads the counters back (waits for the GPU).
    WedgeCounts counts();

private:
    Output mOutput;
    Program mSetup, mDraw, mResolve;
    VertexArray mVao;
    Buffer mWedges, mStats;
    Buffer mIndices; // 24 per wedge: 6 * wedge + its hull corner (kWedgeHullIndex)
    std::size_t mWedgeCapacity = 0;
    std::vector<const void*> mOffsets;
    std::vector<GLsizei> mCounts;
    void drawIndexed(const DrawSet& set);
    std::vector<Query> mQueries; // GL_SAMPLES_PASSED, one per draw() this frame
    std::size_t mQueriesUsed = 0;

};

} // namespace gpu
