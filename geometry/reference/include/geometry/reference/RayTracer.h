// CPU ray-traced visibility with Embree 3: the `raytrace` reference and the hard-shadow check.
// All triangles are two-sided occluders (Embree culls nothing here); alpha-masked materials
// occlude only where their alpha reaches the cutoff (geometry/scene/AlphaMask.h), or, under the
// transmittance rule (RayTraceSettings::transmittance, the `deep-sm` method's), let through
// 1 - alpha of the light at each crossing.
#pragma once

#include <geometry/scene/Scene.h>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace geometry {

struct RayTraceSettings {
    int samples = 1024;       // stratified light samples per point (perfect squares stratify best)
    std::uint32_t seed = 1;   // per-point jitter is derived from this and the point index
    // Origin offset along the normal (and the distance from the origin within which hits are
    // ignored), times the scene bounds diagonal. It only has to clear the error of the surface
    // points given: G-buffer positions lie within ~1e-5 m of their triangle's plane on the game
    // levels (1e-6 of the view distance). Larger offsets bias the result: 1e-4 (6 mm on
    // oa_dm4) moved contact shadows under 5 cm trims by up to 0.37 in V against the GPU
    // reference, and shifted hard-shadow edges by a pixel on the levels.
    float offsetScale = 1e-5f;
    int threads = 0;          // 0 = hardware concurrency
    // The transmittance rule: a light sample contributes the product of (1 - alpha) over every
    // surface its ray crosses (alpha: surfaceAlpha, 1 for opaque materials, the fractional
    // alpha of MASK and BLEND ones, no cutoff) instead of 1 or 0 by the alpha test.
    bool transmittance = false;
};

class RayTracer {
public:
    // Builds one Embree scene from every object whose method is not ShadowMethod::None.
    explicit RayTracer(const Scene& scene);
    // The same from the objects `objects` (indices into scene.objects) only, whatever their
    // method; the bounds that scale the origin offset are still the whole scene's.
    RayTracer(const Scene& scene, std::span<const std::size_t> objects);
    ~RayTracer();
    RayTracer(const RayTracer&) = delete;
    RayTracer& operator=(const RayTracer&) = delete;

    // V = fraction of the light visible from each point (DESIGN.md §2). `points` are surface
    // points, `normals` their geometric normals facing the viewer; the origin is offset along the
    // normal so a surface facing away from the light shadows itself. Entries with a non-finite
    // point get NaN. out.size() == points.size().
    void visibility(const RectLight& light, std::span<const glm::vec3> points,
                    std::span<const glm::vec3> normals, const RayTraceSettings& settings,
                    std::span<float> out) const;

    // 1 or 0: is the light centre visible (hard shadow from the centre), same offset rule.
    void hardVisibility(const glm::vec3& lightPoint, std::span<const glm::vec3> points,
                        std::span<const glm::vec3> normals, const RayTraceSettings& settings,
                        std::span<float> out) const;

    // Every surface along origin + t dir for tnear < t < tfar, in order of t, under the
    // transmittance rule: the translucent ones (alpha in (0, 1)) and the first opaque one, where
    // the list ends. Thread-safe (the deep-sm method's build calls it from many threads).
    void surfacesAlong(const glm::vec3& origin, const glm::vec3& dir, float tnear, float tfar,
                       std::vector<SurfaceHit>& out) const;

    // First hit along a ray (tfar = inf); returns false on a miss. For tests and picking.
    bool intersect(const glm::vec3& origin, const glm::vec3& dir, float& t, glm::vec3& normal) const;

private:
    void build(const Scene& scene, std::span<const std::size_t> objects);

    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

} // namespace geometry
