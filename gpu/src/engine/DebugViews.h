// Debug views (gpu/Renderer.h DebugView), composited into Targets::image after the shade pass:
// - visibility: V as grey (debug-visibility.frag);
// - silhouettes: the frame's directed silhouette edges from the light centre (CasterSet) as
//   lines over the shaded image, depth-tested against the G-buffer with a small relative bias:
//   in front of the surface bright, behind it dim;
// - wedges: drawn by the method (VisibilityMethod::drawDebug → drawWedgeLines): every wedge hull
//   its wedge pass set up this frame, in line mode, bright in front of the surface, dim behind;
// - stencil: its own z-fail volumes from the light centre (as `hard`), then one stencil-tested
//   full-screen draw per count class (0, 1, 2, 3+);
// - group-parts: drawn by the method (wedges-blend) with clearImage and drawPartTiles;
// - error: a reference accumulated over frames (ReferenceSampler: k light samples of the
//   `reference` method's stratified pattern per frame, restarted when the view, light, size or
//   pattern change), its heat map (geometry::errorHeatMap's colours) and mean |dV| (a sum per
//   16x16 tile read back: the one wait of the debug views).
// Programs are built on first use, so the shaded view costs nothing.
#pragma once

#include "engine/Method.h"
#include "passes/FullscreenPass.h"

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gpu {

class WedgePass;
class StencilVolumePass;
class ReferenceSampler;

class DebugViews {
public:
    explicit DebugViews(const ShaderLoader& shaders);
    ~DebugViews();
    DebugViews(const DebugViews&) = delete;
    DebugViews& operator=(const DebugViews&) = delete;

    // Bytes per pixel of the targets the views make at the frame's size (the error view's
    // progressive reference, R32F).
    static constexpr std::size_t kBytesPerPixel = 4;

    // After Targets::resize (the progressive reference restarts).
    void resize(const Targets& t);
    // ctx.settings.debugView into the image (nothing for Shaded); `method` draws its share.
    // Writes ctx.stats.debugNote and referenceSamplesDone.
    void draw(const FrameContext& ctx, VisibilityMethod& method, std::string_view methodName);

    // The progressive reference (Σ 1/N where lit over the samples done) and N / done; a null
    // texture before the error view was first drawn at this size.
    const Texture& referenceSum() const { return mReference; }
    float referenceScale() const;

    // --- For VisibilityMethod::drawDebug ---
    // The hulls of the wedges of `set` that `wedges` set up this frame, as lines over the image.
    void drawWedgeLines(WedgePass& wedges, const Targets& t, const DrawSet& set);
    // The image filled with the background of the views that replace the picture.
    void clearImage(const Targets& t);
    // Part k of `partVisibility` (one part per channel, `parts` <= 4) in tile firstTile + k of a
    // grid x grid mosaic of the view over the image (debug-mosaic.frag).
    void drawPartTiles(const Targets& t, const Texture& partVisibility, int grid, int firstTile,
                       int parts);
    // What the view shows, for FrameStats::debugNote (the method's share may set it).
    std::string note;

private:
    struct ErrorKey {
        glm::mat4 viewProj{1.0f};
        glm::vec3 center{0.0f}, u{0.0f}, v{0.0f};
        int width = 0, height = 0, samples = 0;
        std::uint32_t seed = 0;
        bool operator==(const ErrorKey&) const = default;
    };

    void drawVisibility(const FrameContext& ctx);
    void drawSilhouettes(const FrameContext& ctx);
    void drawStencil(const FrameContext& ctx);
    void drawError(const FrameContext& ctx);
    // One colour line draw with `program` (hidden: behind the surface, dim; else bright).
    void drawLines(const std::function<void(const PipelineState&)>& draw, GLuint program,
                   const glm::vec3& colour, bool polygons);

    const ShaderLoader& mShaders;
    Framebuffer mOverlay; // Targets::image + the shared depth-stencil
    VertexArray mEmptyVao{"debug-views"};
    std::optional<FullscreenPass> mVisibility, mStencilCount, mMosaic, mHeat;
    Program mEdges, mWedgeLines, mErrorSum;
    std::unique_ptr<StencilVolumePass> mVolumes;
    // The progressive reference (error view).
    std::unique_ptr<ReferenceSampler> mSampler;
    Texture mReference;
    Framebuffer mReferenceFbo; // mReference + the shared depth-stencil
    Buffer mSums;
    std::optional<ErrorKey> mErrorKey;
    std::vector<glm::vec2> mPattern;
    int mSamplesDone = 0;
};

} // namespace gpu
