// Occlusion textures, slicing pass (Eisemann & Décoret 2006 §3.4): the casters once from the
// centre of projection behind the light (geometry::OcclusionFrame::sliceProjection), each
// fragment marking its slab's channel in 1–4 RGBA targets (MRT, four slices per target).
// - Binary occupancy as 0/1 in unorm channels, one slice per channel, OR-ed by MAX blending:
//   the paper's layout, which the prefilters read directly (four slices per fetch) — bits packed
//   in an integer target could not be filtered or mipmapped.
// - No depth test and no culling: every triangle occludes from both sides.
// - The leak fix (paper Fig. 6) per object: its fragments also mark the next slab — always (the
//   paper), or only near it (Near: where the sheet comes within sliceDepth * tan(tilt) of the
//   next slab, so that sheets parallel to the slabs are not counted twice).
// - Alpha-tested materials cut their texels out (lib/Material.glsl), so leaves cast and the
//   gaps between them do not.
#pragma once

#include <gpu/gl/ShaderLoader.h>
#include <gpu/gl/State.h>

#include "engine/SceneGeometry.h"

#include <span>

namespace gpu {

class OcclusionSlicePass {
public:
    static constexpr PipelineState kState{
        .blend = true,
        .blendEquation = GL_MAX, // OR of 0/1 occupancy
    };

    // The leak fix of one caster: whether its fragments also mark the next slab.
    enum class LeakFix {
        Off,
        Near,   // where the surface comes within sliceDepth * tan(tilt) of the next slab
        Always, // the paper's rule (flat sheets count twice)
    };
    struct Caster {
        std::size_t object; // scene object
        LeakFix leakFix;
    };

    OcclusionSlicePass(const ShaderLoader& shaders, int slices);
    // Clears `target`'s colour attachments (the slices) and draws the casters into them.
    void execute(const Framebuffer& target, int resolution, const SceneGeometry& geometry,
                 std::span<const Caster> casters) const;

private:
    int mTargets;
    Program mOpaque, mAlphaTested;
};

} // namespace gpu
