#include "passes/WedgePass.h"

#include "engine/ShaderBindings.h"
#include "passes/VolumeStates.h"

#include <geometry/shadow/WedgeHull.h>

#include <algorithm>
#include <cstdint>
#include <utility>

namespace gpu {

WedgePass::WedgePass(const ShaderLoader& shaders, Output output, std::vector<std::string> defines)
    : mOutput(output),
      mSetup(shaders.load({.stages = {{GL_COMPUTE_SHADER, "wedge-setup.comp"}},
                           .defines = output == Output::BitmaskPotential
                                          ? std::vector<std::string>{"WEDGE_APEXES 1"}
                                          : std::vector<std::string>{},
                           .label = "wedge-setup"})),
      mDraw(shaders.load({.stages = {{GL_VERTEX_SHADER, "wedge.vert"},
                                     {GL_FRAGMENT_SHADER, output == Output::Parts4 ? "wedge-parts.frag"
                                                          : output == Output::Bitmask ||
                                                                    output == Output::BitmaskCounts ||
                                                                    output == Output::BitmaskPotential
                                                              ? "wedge-bitmask.frag"
                                                              : "wedge.frag"}},
                          .defines = std::move(defines),
                          .label = "wedges"})),
      mResolve(shaders.load({.stages = {{GL_COMPUTE_SHADER, "wedge-resolve.comp"}},
                             .label = "wedge-resolve"})),
      mVao("wedges"),
      mStats({.size = WEDGE_STAT_COUNT * sizeof(std::uint32_t), .label = "wedge-stats"}) {}

void WedgePass::beginFrame(std::uint32_t edgeCount) {
    const std::size_t needed = std::max<std::size_t>(edgeCount, 1);
    if (needed > mWedgeCapacity) {
        mWedgeCapacity = std::max(needed, 2 * mWedgeCapacity);
        mWedges = Buffer({.size = mWedgeCapacity * sizeof(shader::GpuWedge), .flags = 0,
                          .label = "wedges"});
        // The hull's 8 triangles index its 6 corners (e0, e1, the rays g1..g4): vertex shading
        // runs once per corner, and the post-transform cache of indexed draws reuses it.
        std::vector<std::uint32_t> indices(24 * mWedgeCapacity);
        for (std::size_t w = 0; w < mWedgeCapacity; ++w)
            for (int k = 0; k < geometry::kWedgeHullVertexCount; ++k)
                indices[24 * w + k] = static_cast<std::uint32_t>(6 * w + geometry::kWedgeHullIndex[k]);
        mIndices = Buffer({.size = indices.size() * sizeof(std::uint32_t), .data = indices.data(),
                           .flags = 0, .label = "wedge-indices"});
        mVao.elementBuffer(mIndices);
    }
    const std::uint32_t zero = 0;
    glClearNamedBufferData(mStats.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_WEDGES, mWedges.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_WEDGE_STATS, mStats.id());
    mQueriesUsed = 0;
}

void WedgePass::setup(std::span<const CasterRange> runs, std::uint32_t twinOffset) {
    glUseProgram(mSetup.id());
    if (mOutput == Output::BitmaskPotential) glUniform1ui(1, twinOffset);
    for (const CasterRange& range : runs) {
        if (range.edgeCount == 0) continue;
        glUniform2ui(0, range.firstEdge, range.edgeCount);
        glDispatchCompute((range.edgeCount + 63) / 64, 1, 1);
    }
    // The set-up's buffer writes must be visible to the wedge draws' vertex and fragment shaders.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void WedgePass::drawIndexed(const DrawSet& set) {
    mOffsets.resize(set.edgeFirst.size());
    mCounts.resize(set.edgeCount.size());
    for (std::size_t i = 0; i < set.edgeFirst.size(); ++i) {
        mOffsets[i] = reinterpret_cast<const void*>(static_cast<std::uintptr_t>(set.edgeFirst[i]) *
                                                    24 * sizeof(std::uint32_t));
        mCounts[i] = 24 * set.edgeCount[i];
    }
    glMultiDrawElements(GL_TRIANGLES, mCounts.data(), GL_UNSIGNED_INT, mOffsets.data(),
                        static_cast<GLsizei>(mCounts.size()));
}

void WedgePass::draw(const Framebuffer& target, const Targets& t, const DrawSet& set,
                     const ScissorRect* scissor, bool markTouched, bool countFragments) {
    if (set.edgeFirst.empty()) return;
    // Another wedge pass (auto's, a debug view's) may have bound its own since beginFrame.
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_WEDGES, mWedges.id());
    glBindFramebuffer(GL_FRAMEBUFFER, target.id());
    glViewport(0, 0, t.width, t.height);
    glBindTextureUnit(TEXUNIT_POSITION, t.position.id());
    glUseProgram(mDraw.id());
    glBindVertexArray(mVao.id());
    // One query per draw call of the frame, all read in counts(): reading each at once would
    // stall the pipeline once per batch.
    if (countFragments) {
        if (mQueriesUsed == mQueries.size()) mQueries.emplace_back(GL_SAMPLES_PASSED);
        glBeginQuery(GL_SAMPLES_PASSED, mQueries[mQueriesUsed++].id());
    }
    // Entry faces (uPass 0), then exit faces (uPass 1): wedge.vert.
    for (GLuint drawPass = 0; drawPass < 2; ++drawPass) {
        PipelineState state = drawPass == 0 ? kEntryState : kExitState;
        if (mOutput == Output::Parts4) {
            // Sums by ADD (coverage, corner windings: targets 0-3), bounds by MIN (4-7).
            state.independentTargets = true;
            for (int i = 0; i < 8; ++i)
                state.targets[i] = ColorTargetState{
                    .blend = true, .blendEquation = i < 4 ? GLenum(GL_FUNC_ADD) : GLenum(GL_MIN)};
            for (int i = 0; i < 4; ++i) state.targets[i].blendDst = GL_ONE;
        }
        if (mOutput == Output::Bitmask) {
            // Masks by XOR: integer targets, where blending does not apply.
            state.blend = false;
            state.logicOp = true;
            state.logicOpMode = GL_XOR;
        }
        if (mOutput == Output::BitmaskCounts) {
            state.blend = false; // image atomics only
            state.colorWrite = false;
        }
        if (mOutput == Output::BitmaskPotential) {
            state.blendEquation = GL_FUNC_ADD; // A += m coverage (and counts by image atomics)
        }
        if (markTouched) {
            const StencilFace mark{.func = GL_ALWAYS,
                                   .ref = GLint(kStencilWedgeMark),
                                   .depthPass = GL_REPLACE};
            state.stencilTest = true;
            state.stencilWriteMask = kStencilWedgeMark;
            state.stencilFront = mark;
            state.stencilBack = mark;
        }
        if (scissor) {
            state.scissor = true;
            state.scissorRect = *scissor;
        }
        applyState(state);
        glUniform1ui(0, drawPass);
        drawIndexed(set);
    }
    if (countFragments) glEndQuery(GL_SAMPLES_PASSED);
}

void WedgePass::drawHulls(const Framebuffer& target, const Targets& t, const DrawSet& set,
                          GLuint program, const PipelineState& state) {
    if (set.edgeFirst.empty()) return;
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_WEDGES, mWedges.id());
    glBindFramebuffer(GL_FRAMEBUFFER, target.id());
    glViewport(0, 0, t.width, t.height);
    glUseProgram(program);
    glBindVertexArray(mVao.id());
    applyState(state);
    for (GLuint drawPass = 0; drawPass < 2; ++drawPass) {
        glUniform1ui(0, drawPass);
        drawIndexed(set);
    }
}

void WedgePass::bindWedges() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_WEDGES, mWedges.id());
}

void WedgePass::resolve(const Targets& t) {
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    glUseProgram(mResolve.id());
    glBindImageTexture(IMAGE_VISIBILITY, t.visibility.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                       GL_R32F);
    glDispatchCompute(static_cast<GLuint>((t.width + 7) / 8),
                      static_cast<GLuint>((t.height + 7) / 8), 1);
    // V is sampled by the shading pass and read back next.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                    GL_BUFFER_UPDATE_BARRIER_BIT);
}

WedgeCounts WedgePass::counts() {
    std::array<std::uint32_t, WEDGE_STAT_COUNT> s{};
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT); // the set-up's and resolve's atomics
    glGetNamedBufferSubData(mStats.id(), 0, sizeof(s), s.data());
    WedgeCounts c;
    c.bounded = s[WEDGE_BOUNDED];
    c.fullscreen = s[WEDGE_FULLSCREEN];
    c.degenerate = s[WEDGE_DEGENERATE];
    c.culled = s[WEDGE_CULLED];
    c.clampedPixels = s[WEDGE_STAT_CLAMPED];
    c.eyeInside = s[WEDGE_STAT_EYE_INSIDE];
    c.cones = s[WEDGE_STAT_CONES];
    for (std::size_t q = 0; q < mQueriesUsed; ++q) {
        GLuint64 samples = 0;
        glGetQueryObjectui64v(mQueries[q].id(), GL_QUERY_RESULT, &samples);
        c.fragments += samples;
    }
    return c;
}

} // namespace gpu
