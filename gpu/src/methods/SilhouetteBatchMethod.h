// The frame driver of the per-silhouette methods: batches of silhouette groups that cannot
// interact on screen (GroupBatches.h), each through the same pass sequence.
#pragma once

#include "engine/Method.h"
#include "methods/GroupBatches.h"
#include "passes/StencilVolumePass.h"
#include "passes/SurfaceTilePass.h"
#include "passes/WedgePass.h"

#include <gpu/gl/Objects.h>
#include <gpu/gl/State.h>

namespace gpu {

struct TouchedStates {
    PipelineState lit, occluded, touched;
};
struct UmbraStates {
    PipelineState keep, zero;
};

// `base` with the stencil test and scissor of `stencil` (a state given to combine or reset).
inline PipelineState withStencil(PipelineState base, const PipelineState& stencil) {
    base.stencilTest = stencil.stencilTest;
    base.stencilWriteMask = stencil.stencilWriteMask;
    base.stencilFront = stencil.stencilFront;
    base.stencilBack = stencil.stencilBack;
    base.scissor = stencil.scissor;
    base.scissorRect = stencil.scissorRect;
    return base;
}

// The frame of the per-silhouette methods (multiply, blend, bitmask), which derive from this
// class and supply its three steps: the visible surface's tiles (SurfaceTilePass: a wait for
// the G-buffer; skipped as visibleSets skips it); batches; every wedge set up once; the stencil
// cleared once; then per batch, scissored to it:
// 1. the batch's groups' z-fail volumes: the count in the stencil's low bits (VolumeStates.h);
// 2. their wedges (GroupBatch::wedgeSet) into runBatches' `target` (the method's per-silhouette
//    targets, holding their empty values everywhere), marking the touched pixels in the
//    stencil (kStencilWedgeMark);
// 3. combine() where a wedge touched: the method draws its combine pass under `lit` (the
//    group leaves the light centre visible there) and `occluded` (it hides it); `touched`
//    selects both without changing the stencil (for a method that needs several rounds, e.g.
//    wedges-blend's part sets: reset its targets and draw the wedges again in between);
// 4. reset() where a wedge touched: the per-silhouette targets back to their empty values
//    (the given state zeroes those pixels' stencil);
// 5. umbra() where no wedge touched but the count is non-zero (the group's umbra: its state
//    there is the full occlusion): drawn under `keep`, the last draw under `zero`, which
//    zeroes the stencil there.
// The stencil and the per-silhouette targets are thus clean again after every batch, touched
// only where the batch drew: no per-batch clears. Where no group's wedge or volume reaches, the
// final buffer is never touched. Adds the batch and wedge counters to the report
// ("groups_hidden", "wedges_hidden": left out by the surface tiles; "wedges_drawn";
// "pixels_blended": the samples of step 3's draws — the touched pixels, once per round of a
// method that needs several —, "pixels_umbra": those of step 5, summed over batches, by
// occlusion queries).
class SilhouetteBatchMethod : public VisibilityMethod {
protected:
    // `wedges`: the method's wedge pass (its output and defines).
    SilhouetteBatchMethod(const ShaderLoader& shaders, WedgePass wedges);

    // Steps 1-5 for every batch, the wedges drawn into `target`.
    void runBatches(const FrameContext& ctx, const Framebuffer& target);

    virtual void combine(const FrameContext& ctx, const GroupBatch& batch,
                         const TouchedStates& states) = 0;
    virtual void reset(const FrameContext& ctx, const GroupBatch& batch,
                       const PipelineState& stencil) = 0;
    virtual void umbra(const FrameContext& ctx, const GroupBatch& batch,
                       const UmbraStates& states) = 0;

    SurfaceTilePass mSurface;
    StencilVolumePass mVolumes;
    WedgePass mWedges;
};

} // namespace gpu
