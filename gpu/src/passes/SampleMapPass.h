// Sample maps, shadow pass: one shadow map per light sample (geometry/shadow/SampleMapFrame.h),
// each a perspective view from its sample point fitted to the casters' box, drawn into the
// layers of a depth-array texture with SampleMapFrame::projection.
// - Depth only, zNear / z, reversed: cleared to 0 (nothing), GREATER keeps the nearest surface.
// - No culling: every triangle occludes from both sides, as in pcss's maps.
// - Alpha-tested materials cut their texels out (lib/Material.glsl), as in the G-buffer.
// Used by `sample-maps` (every map at once, read by its lookup) and `pdsm` (a few layers at a
// time, read back and merged into the deep map on the CPU).
#pragma once

#include <geometry/scene/Scene.h>
#include <geometry/shadow/SampleMapFrame.h>
#include <gpu/gl/Objects.h>
#include <gpu/gl/ShaderLoader.h>

#include "engine/CasterSet.h"
#include "engine/SceneGeometry.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace gpu {

class SampleMapPass {
public:
    // `layers` maps of `resolution`^2 texels (GL_DEPTH_COMPONENT32F).
    SampleMapPass(const ShaderLoader& shaders, int layers, int resolution, const char* label);

    // Clears layers 0..count-1 and draws views first..first + count - 1 of `frame` into them,
    // each with `objects` (scene objects). `slopeBias` > 0: every surface is stored that many
    // texels' worth of its own depth slope farther from the sample (glPolygonOffset), so that a
    // surface the sample grazes does not hide its own points in the texels it spans.
    void draw(const geometry::SampleMapFrame& frame, std::size_t first, std::size_t count,
              std::span<const std::size_t> objects, const SceneGeometry& geometry,
              float slopeBias = 0.0f) const;

    const Texture& maps() const { return mMaps; }
    int resolution() const { return mResolution; }
    int layers() const { return mLayers; }

private:
    Program mOpaque, mAlphaTested;
    Texture mMaps;
    std::vector<Framebuffer> mFbos;
    int mResolution = 0, mLayers = 0;
};

// The frame of the sample maps for a method's casters: their scene objects, and the frame fitted
// to their bounds from `samples` stratified points of the light (the reference's pattern for
// that count and `seed`).
struct SampleMapSetup {
    std::vector<std::size_t> objects;
    geometry::Aabb bounds;
    geometry::SampleMapFrame frame;
};
SampleMapSetup fitSampleMaps(const geometry::Scene& scene, const CasterSet& casters,
                             std::span<const std::uint32_t> casterSubset,
                             const geometry::RectLight& light, int samples, std::uint32_t seed);
// The same from the given points of the light ((s, t) in [-1, 1]^2 over its half axes).
SampleMapSetup fitSampleMaps(const geometry::Scene& scene, const CasterSet& casters,
                             std::span<const std::uint32_t> casterSubset,
                             const geometry::RectLight& light, std::span<const glm::vec2> points);

} // namespace gpu
