#include <geometry/shadow/SampleMapFrame.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace geometry {

namespace {

std::array<glm::vec3, 8> corners(const Aabb& b) {
    std::array<glm::vec3, 8> c;
    for (int i = 0; i < 8; ++i)
        c[i] = glm::vec3((i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
                         (i & 4) ? b.max.z : b.min.z);
    return c;
}

struct Axes {
    glm::vec3 eu, ev, n;
};

// The light's frame with n towards the box's centre.
Axes axesFor(const RectLight& light, const Aabb& box) {
    Axes a;
    a.n = light.normal();
    if (glm::dot(0.5f * (box.min + box.max) - light.center, a.n) < 0.0f) a.n = -a.n;
    a.eu = glm::normalize(light.u - glm::dot(light.u, a.n) * a.n);
    a.ev = glm::cross(a.n, a.eu);
    return a;
}

// The box seen from `origin`: its least and greatest depth and its extent in m, each corner's
// depth held at least kSampleMapMinDepthShare of the greatest (clipped: it was not) and m at
// the cap.
struct Seen {
    float zNear, zFar;
    glm::vec2 lo, hi;
    bool clipped;
};

Seen seenFrom(const Axes& a, const glm::vec3& origin, const std::array<glm::vec3, 8>& box) {
    Seen s{std::numeric_limits<float>::max(), 0.0f, glm::vec2(kSampleMapMaxTan),
           glm::vec2(-kSampleMapMaxTan), false};
    for (const glm::vec3& q : box) s.zFar = std::max(s.zFar, glm::dot(q - origin, a.n));
    const float zMin = kSampleMapMinDepthShare * s.zFar;
    for (const glm::vec3& q : box) {
        const glm::vec3 d = q - origin;
        float z = glm::dot(d, a.n);
        if (z < zMin) {
            s.clipped = true;
            z = zMin;
        }
        s.zNear = std::min(s.zNear, z);
        const glm::vec2 m = glm::vec2(glm::dot(d, a.eu), glm::dot(d, a.ev)) / z;
        s.lo = glm::min(s.lo, m);
        s.hi = glm::max(s.hi, m);
    }
    for (int k = 0; k < 2; ++k) {
        if (s.lo[k] < -kSampleMapMaxTan || s.hi[k] > kSampleMapMaxTan) s.clipped = true;
        s.lo[k] = std::clamp(s.lo[k], -kSampleMapMaxTan, kSampleMapMaxTan);
        s.hi[k] = std::clamp(s.hi[k], -kSampleMapMaxTan, kSampleMapMaxTan);
        // A margin of a thousandth of the extent (and never an empty one), so that rasterised
        // triangles on the box's faces stay inside the map.
        const float margin = std::max(1e-3f * (s.hi[k] - s.lo[k]), 1e-6f);
        s.lo[k] -= margin;
        s.hi[k] += margin;
    }
    s.zNear *= 0.999f;
    return s;
}

} // namespace

glm::mat4 SampleMapFrame::projection(std::size_t i) const {
    const SampleMapView& v = views[i];
    const glm::vec3 rx = (2.0f * eu - (v.lo.x + v.hi.x) * n) / (v.hi.x - v.lo.x);
    const glm::vec3 ry = (2.0f * ev - (v.lo.y + v.hi.y) * n) / (v.hi.y - v.lo.y);
    const glm::vec4 rows[4] = {glm::vec4(rx, -glm::dot(rx, v.origin)),
                               glm::vec4(ry, -glm::dot(ry, v.origin)),
                               glm::vec4(0.0f, 0.0f, 0.0f, viewNear(i)),
                               glm::vec4(n, -glm::dot(n, v.origin))};
    glm::mat4 m(0.0f);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            m[c][r] = rows[r][c];
    return m;
}

SampleMapFrame fitSampleMapFrame(const RectLight& light, std::span<const glm::vec2> samples,
                                 const Aabb& casters) {
    SampleMapFrame f;
    if (casters.empty()) return f;
    const Axes a = axesFor(light, casters);
    f.eu = a.eu;
    f.ev = a.ev;
    f.n = a.n;
    f.empty = false;
    const std::array<glm::vec3, 8> box = corners(casters);
    const Seen centre = seenFrom(a, light.center, box);
    // The light's half extent along each lateral axis.
    const glm::vec2 half(std::abs(glm::dot(light.u, a.eu)) + std::abs(glm::dot(light.v, a.eu)),
                         std::abs(glm::dot(light.u, a.ev)) + std::abs(glm::dot(light.v, a.ev)));
    f.zNear = centre.zNear;
    f.clipped = centre.clipped;
    for (const glm::vec2& s : samples) {
        SampleMapView v;
        v.st = s;
        v.origin = light.point(s.x, s.y);
        const Seen seen = seenFrom(a, v.origin, box);
        f.clipped = f.clipped || seen.clipped;
        v.lo = seen.lo;
        v.hi = seen.hi;
        f.views.push_back(v);
    }
    f.centreLo = centre.lo;
    f.centreHi = centre.hi;
    f.half = half;
    f.zFar = centre.zFar;
    f.reachAll = f.clipped;
    return f;
}

bool inReach(const SampleMapFrame& f, const glm::vec3& lightCenter, const glm::vec3& p) {
    if (f.empty) return false;
    if (f.reachAll) return true;
    const glm::vec3 d = p - lightCenter;
    const float z = glm::dot(d, f.n);
    if (z <= f.zNear) return false; // nearer than every caster (0.999 of the box's near depth)
    const glm::vec2 m = glm::vec2(glm::dot(d, f.eu), glm::dot(d, f.ev)) / z;
    const float spread = std::max(std::abs(1.0f / z - 1.0f / f.zNear),
                                  std::abs(1.0f / z - 1.0f / f.zFar));
    // The maps' margins (a thousandth of their extent, seenFrom) and rounding: 1 %.
    const glm::vec2 slack = 0.01f * (f.centreHi - f.centreLo) + f.half * spread;
    return glm::all(glm::greaterThanEqual(m, f.centreLo - slack)) &&
           glm::all(glm::lessThanEqual(m, f.centreHi + slack));
}

bool sampleMapsHold(const RectLight& light, const Aabb& casters) {
    if (casters.empty()) return true;
    const Axes a = axesFor(light, casters);
    const std::array<glm::vec3, 8> box = corners(casters);
    // Depth and m are each monotone along the light's straight edges for a fixed corner, and
    // the extremes of m over the light lie at its corners when every depth stays positive.
    for (int k = 0; k < 4; ++k) {
        const glm::vec3 origin =
            light.point((k & 1) ? 1.0f : -1.0f, (k & 2) ? 1.0f : -1.0f);
        if (seenFrom(a, origin, box).clipped) return false;
    }
    return true;
}

} // namespace geometry
