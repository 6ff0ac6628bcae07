// The pcss method's shadow maps and lookup (Fernando 2005), as one piece the methods share
// (pcss; occlusion's fallback; deep-sm, whose maps are deep shadow maps, below):
// - frame (CPU, geometry::fitPcssFrame, redone when the light or the casters change, and the
//   maps with it: a still light reuses them, counted as pcss_maps_cached): the faces
//   of a cube around the light's centre that have receivers: along ±n fitted to the receivers
//   within a 71.6° half-angle, along the light's lateral axes for every receiver beyond it
//   (walls reaching the light's plane), and the casters' near depth in each;
// - shadow pass (passes/PcssShadowPass): the casters into the maps, alpha-tested ones cut out;
// - lookup (pcss-lookup.frag): per G-buffer point, blocker search, penumbra width
//   w = lightSize (zReceiver - zBlocker) / zBlocker per light axis, percentage-closer filtering
//   over that rectangle; depth compared with the receiver's plane moved `bias` texels towards
//   the light; V times the light's share in front of the surface (`horizon`, as occlusion's).
//   V is written at every pixel.
// A receiver whose segment to the light's centre misses every box around the casters'
// occluding points (geometry::casterClusters, 16 at most: an alpha-tested triangle boxed around
// its opaque texels only) grown by the light's half extents is lit without a search (only the
// horizon term applies; `pcss_pixels_searched` counts the others): the alpha path's few grates,
// flames and light beams on a level leave most pixels there, even with the lamp among them.
// Receivers within zNear of the light's centre (in no face) get V = 1 and, where a caster's
// box could reach them, are counted
// (`pcss_pixels_outside`). The occlusion method owns one for the receivers its slicing frustum
// cannot cover (Pixels::OutsideOcclusion).
// With DeepSmOptions (the deep-sm method, Lokovic & Veach 2000), the faces' maps are deep shadow
// maps (geometry/shadow/DeepShadowMap.h), built on the CPU by tracing the casters
// (geometry::RayTracer::surfacesAlong, the transmittance rule) when the frame is fitted again,
// and the lookup (pcss-lookup.frag with DEEP_SHADOW_MAP) reads each texel's transmittance at the
// receiver's plane where pcss compares depths.
#pragma once

#include "engine/Method.h"
#include "engine/MethodOptions.h"
#include "engine/ShaderBindings.h"
#include "passes/FullscreenPass.h"
#include "passes/PcssShadowPass.h"

#include <geometry/shadow/PcssFrame.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace gpu {

class PcssShadow {
public:
    // Which pixels the lookup writes: every one (the pcss method), or those the occlusion
    // method's slicing frustum does not cover (geometry::OcclusionFrame::covers; its uniforms
    // bound), which it would otherwise draw lit.
    enum class Pixels { All, OutsideOcclusion };

    PcssShadow(const MethodResources& r, const PcssOptions& o, Pixels pixels = Pixels::All);
    // deep-sm: the same frame and lookup over deep shadow maps.
    explicit PcssShadow(const MethodResources& r, const DeepSmOptions& deep);
    ~PcssShadow();

    // Fits the frame and draws the maps if the light or the casters changed (else the last
    // frame's maps are reused: they do not depend on the camera), and writes V of the pixels
    // into the visibility target; adds the pcss_* counters (All) or occlusion_pixels_outside,
    // occlusion_outside_maps and occlusion_outside_maps_cached (OutsideOcclusion).
    // `multiply`: the lookup multiplies V into the target's (VisibilityMethod::executeMultiplied)
    // instead of writing it.
    void execute(const FrameContext& ctx, bool multiply = false);

private:
    PcssShadow(const MethodResources& r, const PcssOptions& o, Pixels pixels, bool deep);
    // A face's map is drawn when casters reach into its frustum and receivers lie in it or in
    // a face beside it (geometry::PcssFace::drawn).
    bool drawn(int face) const { return mFrame.faces[face].drawn; }
    void updateFrame(const FrameContext& ctx);
    // deep-sm: traces and uploads the deep map of the frame's faces.
    void buildDeep(const FrameContext& ctx);
    void deepCounters(const FrameContext& ctx, bool cached, std::uint32_t outside) const;
    // The lookup over the frame's surface tiles (FrameScratch) that the reach test can pass
    // for (geometry::sweepMeetsBox), the horizon term alone over the others; false, nothing
    // drawn, where the tiles are not known (the lookup then covers the screen).
    bool drawLookupOverTiles(const FrameContext& ctx, bool multiply);
    // mCasterBoxes grown by `light`'s half extents: the reach test's boxes (the shader's per
    // pixel, drawLookupOverTiles's per tile; kept for the frame in mReach).
    std::vector<geometry::Aabb> reachBoxes(const geometry::RectLight& light) const;

    struct Deep; // deep-sm's options, tracer, map and its textures
    std::unique_ptr<Deep> mDeep;
    Pixels mPixels;
    int mResolution, mSearchSamples, mFilterSamples;
    PcssShadowPass mShadowPass;
    FullscreenPass mLookup;
    // The same lookup over rectangles of tiles (tile-rects.vert), and its horizon term alone
    // for the tiles no caster reaches (HORIZON_ONLY; only with horizon=on).
    FullscreenPass mLookupTiles;
    std::optional<FullscreenPass> mHorizonTiles;
    Texture mMaps;
    Framebuffer mFaceFbo[geometry::kPcssFaces];
    glm::vec4 mPattern[PCSS_MAX_SAMPLES];
    Buffer mUniforms;
    Buffer mStats;
    Buffer mRects; // BINDING_SCREEN_RECTS: the reached tiles' rectangles, then the others'

    bool mFitted = false;
    bool mMapsDrawn = false; // the maps hold mFrame's casters (reused while it stands)
    geometry::RectLight mLight;
    std::vector<std::uint32_t> mSubset;
    std::vector<std::size_t> mObjects;
    std::vector<geometry::Aabb> mCasterBoxes; // geometry::casterClusters of mObjects
    std::vector<geometry::Aabb> mReach;       // this frame's reachBoxes
    geometry::PcssFrame mFrame;
};

} // namespace gpu
