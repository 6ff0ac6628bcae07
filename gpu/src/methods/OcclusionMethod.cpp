// occlusion: occlusion textures (Eisemann & Décoret 2006; DESIGN.md §4), for any geometry,
// alpha-tested foliage included:
// - frame (CPU, geometry::fitOcclusionFrame, redone when the light or the casters change, and
//   the slices and prefilter with it: a still light reuses them, occlusion_slices_cached): the
//   centre of projection behind the light, the frustum fitted to the light, the slices over the
//   depth range that holds the casters inside the frustum (from their triangles' vertices);
// - slicing pass (passes/OcclusionSlicePass): the casters once into 4, 8 or 16 binary slices,
//   four per RGBA target (MRT); the leak fix per caster (auto: open, non-manifold or
//   alpha-tested casters — thin sheets — and not closed ones), marking the next slab where a
//   sheet comes near it (paper: everywhere);
// - prefilter (passes/OcclusionPrefilter): N-buffers (default), summed-area tables or mipmaps;
// - lookup (occlusion-lookup.frag): per G-buffer point, V = Π (1 - w_k I_k) over the slices in
//   front of it (geometry/shadow/OcclusionSlices.h explains the kernel and the fade), times the share
//   of the light in front of the surface (horizon=on; not in the paper);
// - outside=pcss (default): the receivers the slicing frustum cannot hold (behind or in the
//   light's plane, beyond the capped frustum: a room's walls and ceiling around a lamp, which
//   the paper would draw lit) are shadowed from pcss's shadow maps (methods/PcssShadow, its
//   default parameters), only when the frame finds such receivers, and counted.
// V is written (not multiplied) at every pixel; casters outside the subset are not sliced.
#include "engine/Method.h"
#include "engine/MethodOptions.h"
#include "engine/ShaderBindings.h"
#include "passes/FullscreenPass.h"
#include "passes/OcclusionPrefilter.h"
#include "passes/OcclusionSlicePass.h"
#include "methods/PcssShadow.h"

#include <geometry/shadow/OcclusionSlices.h>

#include <cmath>
#include <optional>
#include <string>

namespace gpu {

namespace {

using Prefilter = OcclusionPrefilter;
using LeakFix = OcclusionLeakFix;

int log2Int(int x) {
    int l = 0;
    while ((1 << (l + 1)) <= x) ++l;
    return l;
}

class OcclusionMethod final : public VisibilityMethod {
public:
    explicit OcclusionMethod(const MethodResources& r)
        : OcclusionMethod(r, occlusionOptions(r.parameters)) {}

    OcclusionMethod(const MethodResources& r, const OcclusionOptions& o)
        : mSlices(o.slices), mResolution(o.resolution), mPrefilter(o.prefilter),
          mLeakFix(o.leakFix), mHorizon(o.horizon), mOutsidePcss(o.outsidePcss),
          mTargets((mSlices + 3) / 4), mTopLevel(log2Int(mResolution)),
          mSlicePass(r.shaders, mSlices),
          mLookup(r.shaders, "occlusion-lookup.frag", "occlusion-lookup", PipelineState{},
                  lookupDefines()) {
        if (o.outsidePcss)
            mOutside.emplace(r,
                             pcssOptions(std::vector<ParameterValue>{
                                 {"horizon", o.horizon ? "on" : "off"}}),
                             PcssShadow::Pixels::OutsideOcclusion);
        const int R = mResolution;
        switch (mPrefilter) {
        case Prefilter::NBuffers:
            // Level 0 (what the slicing pass draws) and the levels above it in one array, so
            // that one sampler reads them all: layer = level * targets + target. 16 bits:
            // means of 0/1 texels, rounded once per level.
            mLevels = Texture({.target = GL_TEXTURE_2D_ARRAY, .width = R, .height = R,
                               .layers = (mTopLevel + 1) * mTargets, .format = GL_RGBA16,
                               .minFilter = GL_LINEAR, .magFilter = GL_LINEAR,
                               .wrap = GL_CLAMP_TO_BORDER, .label = "occlusion-nbuffers"});
            mNBuffers.emplace(r.shaders, mSlices);
            break;
        case Prefilter::Mipmaps:
            mLevels = Texture({.target = GL_TEXTURE_2D_ARRAY, .width = R, .height = R,
                               .layers = mTargets, .format = GL_RGBA8, .levels = mTopLevel + 1,
                               .minFilter = GL_LINEAR_MIPMAP_LINEAR, .magFilter = GL_LINEAR,
                               .wrap = GL_CLAMP_TO_BORDER, .label = "occlusion-slices-mipmapped"});
            break;
        case Prefilter::Sat:
            mLevels = Texture({.target = GL_TEXTURE_2D_ARRAY, .width = R, .height = R,
                               .layers = mTargets, .format = GL_RGBA8,
                               .label = "occlusion-slices"});
            mSat = Texture({.target = GL_TEXTURE_2D_ARRAY, .width = R + 1, .height = R + 1,
                            .layers = mTargets, .format = GL_RGBA32UI, .label = "occlusion-sat"});
            mSatPass.emplace(r.shaders);
            break;
        }
        FramebufferDesc fbo{.label = "occlusion-slices"};
        for (int t = 0; t < mTargets; ++t)
            fbo.attachments.push_back({GLenum(GL_COLOR_ATTACHMENT0 + t), &mLevels, 0, t});
        mSliceFbo = Framebuffer(fbo);
    }

    void execute(const FrameContext& ctx) override {
        updateFrame(ctx);
        const geometry::OcclusionFrame& f = mFrame;
        // Levels the widest kernel can need: (z_P - z_0) / z_P < 1 of the light seen through
        // the first plane, magnified by d / (d + z_0).
        int top = 0;
        if (mPrefilter == Prefilter::Mipmaps) {
            top = mTopLevel;
        } else if (mPrefilter == Prefilter::NBuffers && !f.empty) {
            const float widest = mResolution / f.magnification(f.planeDepth(0));
            top = std::clamp(static_cast<int>(std::ceil(std::log2(std::max(widest, 1.0f)))), 0,
                             mTopLevel);
        }
        shader::OcclusionUniforms u{};
        u.sliceProj = f.sliceProjection();
        u.axis = glm::vec4(f.axis, f.copDistance);
        u.range = glm::vec4(f.zNear, f.sliceDepth(), static_cast<float>(f.slices),
                            f.empty ? 1.0f : 0.0f);
        u.texels = glm::vec4(static_cast<float>(mResolution), 1.0f / static_cast<float>(mResolution),
                             static_cast<float>(top), 0.0f);
        mUniforms.upload(&u, sizeof(u));
        glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_OCCLUSION_UBO, mUniforms.id());

        // The slices and their prefilter depend on the light and the casters only: a still
        // light reuses the last frame's.
        const bool cached = mSlicesDrawn;
        if (!f.empty && !cached) {
            {
                ScopedPass pass(&ctx.timers, "occlusion-slice");
                mSlicePass.execute(mSliceFbo, mResolution, ctx.sceneGeometry, mCasters);
            }
            ScopedPass pass(&ctx.timers, "occlusion-prefilter");
            switch (mPrefilter) {
            case Prefilter::NBuffers:
                mNBuffers->execute(mLevels, top);
                break;
            case Prefilter::Mipmaps:
                glGenerateTextureMipmap(mLevels.id());
                break;
            case Prefilter::Sat:
                mSatPass->execute(mLevels, mSat);
                break;
            }
        }
        mSlicesDrawn = true;
        {
            ScopedPass pass(&ctx.timers, "occlusion-lookup");
            glBindTextureUnit(TEXUNIT_POSITION, ctx.targets.position.id());
            glBindTextureUnit(TEXUNIT_NORMAL, ctx.targets.normal.id());
            glBindTextureUnit(TEXUNIT_OCCLUSION,
                              mPrefilter == Prefilter::Sat ? mSat.id() : mLevels.id());
            mLookup.execute(ctx.targets.visibilityFbo, ctx.targets.width, ctx.targets.height);
        }
        // The receivers the frustum cannot hold: from pcss's maps, over the pixels not covered.
        if (mOutside) {
            if (f.receiversOutside) {
                mOutside->execute(ctx);
            } else {
                ctx.addCounter("occlusion_pixels_outside", 0.0);
                ctx.addCounter("occlusion_outside_maps", 0.0);
            }
        }

        ctx.addCounter("occlusion_slices", mSlices);
        ctx.addCounter("occlusion_resolution", mResolution);
        ctx.addCounter("occlusion_z_near", f.empty ? 0.0 : f.zNear);
        ctx.addCounter("occlusion_z_far", f.empty ? 0.0 : f.zFar);
        ctx.addCounter("occlusion_cop_distance", f.copDistance);
        ctx.addCounter("occlusion_magnification", f.empty ? 0.0 : f.magnification(f.zFar));
        ctx.addCounter("occlusion_prefilter_levels", top);
        ctx.addCounter("occlusion_slices_cached", cached ? 1.0 : 0.0);
        std::size_t leakFixed = 0;
        for (const auto& c : mCasters) leakFixed += c.leakFix != OcclusionSlicePass::LeakFix::Off;
        ctx.addCounter("occlusion_casters", static_cast<double>(mCasters.size()));
        ctx.addCounter("occlusion_casters_leakfix", static_cast<double>(leakFixed));
    }

private:
    std::vector<std::string> lookupDefines() const {
        std::vector<std::string> d = {"SLICES " + std::to_string(mSlices), prefilterDefine()};
        if (mHorizon) d.push_back("HORIZON");
        if (mOutsidePcss) d.push_back("OUTSIDE_PCSS");
        return d;
    }
    std::string prefilterDefine() const {
        switch (mPrefilter) {
        case Prefilter::Sat:
            return "PREFILTER_SAT";
        case Prefilter::Mipmaps:
            return "PREFILTER_MIPMAPS";
        case Prefilter::NBuffers:
            break;
        }
        return "PREFILTER_NBUFFERS";
    }

    // The frame and the casters' list, refitted when the light or the subset changes.
    void updateFrame(const FrameContext& ctx) {
        const geometry::RectLight& light = ctx.light;
        std::vector<std::uint32_t> subset(ctx.casterSubset.begin(), ctx.casterSubset.end());
        if (mFitted && light == mLight && subset == mSubset)
            return;
        const auto t0 = Clock::now();
        std::vector<std::size_t> objects;
        mCasters.clear();
        for (const std::uint32_t c : subset) {
            const std::size_t object = ctx.casters.sceneObject(c);
            objects.push_back(object);
            // Thin sheets leak between slices (paper Fig. 6): open and non-manifold meshes
            // (cards, planes, level geometry) and alpha-tested ones (leaves); closed meshes have
            // a back side in the slices behind their front.
            const bool thin =
                ctx.casters.topology(c).manifoldness() != geometry::Manifoldness::Closed ||
                ctx.sceneGeometry.alphaTested(object);
            using Fix = OcclusionSlicePass::LeakFix;
            Fix fix = Fix::Off;
            if (mLeakFix == LeakFix::Paper) fix = Fix::Always;
            if (mLeakFix == LeakFix::On || (mLeakFix == LeakFix::Auto && thin)) fix = Fix::Near;
            mCasters.push_back({object, fix});
        }
        mFrame = geometry::fitOcclusionFrame(ctx.scene, light, objects, mSlices);
        mSlicesDrawn = false;
        mLight = light;
        mSubset = std::move(subset);
        mFitted = true;
        ctx.addCpuTime("occlusion-fit", msSince(t0));
    }

    int mSlices, mResolution;
    Prefilter mPrefilter;
    LeakFix mLeakFix;
    bool mHorizon;
    bool mOutsidePcss; // before mLookup: its defines read it
    int mTargets, mTopLevel;
    OcclusionSlicePass mSlicePass;
    FullscreenPass mLookup;
    std::optional<NBufferPass> mNBuffers;
    std::optional<SatPass> mSatPass;
    Texture mLevels, mSat;
    Framebuffer mSliceFbo;
    Buffer mUniforms{{.size = sizeof(shader::OcclusionUniforms), .label = "occlusion-uniforms"}};
    std::optional<PcssShadow> mOutside; // outside=pcss

    bool mFitted = false;
    bool mSlicesDrawn = false; // the slices and levels hold mFrame's casters
    geometry::RectLight mLight;
    std::vector<std::uint32_t> mSubset;
    std::vector<OcclusionSlicePass::Caster> mCasters;
    geometry::OcclusionFrame mFrame;
};

} // namespace

std::unique_ptr<VisibilityMethod> createOcclusionMethod(const MethodResources& r) {
    return std::make_unique<OcclusionMethod>(r);
}

} // namespace gpu
