// The PCSS shadow maps' frame (geometry/shadow/PcssFrame.h).
#include <geometry/shadow/PcssFrame.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace geometry {

namespace {

// A triangle clipped to half-spaces stays a convex polygon of at most 3 + 5 vertices.
struct Polygon {
    glm::vec3 p[8];
    int count = 0;
};

// Keeps the part where dot(w, p) + w0 >= 0 (Sutherland-Hodgman, one plane).
Polygon clip(const Polygon& in, const glm::vec3& w, float w0) {
    Polygon out;
    for (int i = 0; i < in.count; ++i) {
        const glm::vec3 a = in.p[i], b = in.p[(i + 1) % in.count];
        const float ga = glm::dot(w, a) + w0, gb = glm::dot(w, b) + w0;
        if (ga >= 0.0f) out.p[out.count++] = a;
        if ((ga >= 0.0f) != (gb >= 0.0f) && out.count < 8)
            out.p[out.count++] = a + (ga / (ga - gb)) * (b - a);
    }
    return out;
}

// The triangle in a side's local coordinates (x, y, z): lateral, then depth.
Polygon local(const PcssFrame& f, int side, const glm::vec3& a, const glm::vec3& b,
              const glm::vec3& c) {
    Polygon t;
    for (const glm::vec3& q : {a, b, c})
        t.p[t.count++] = glm::vec3(f.lateral(q), f.depth(q, side));
    return t;
}

} // namespace

glm::vec2 PcssFrame::textureCoord(const glm::vec3& q, int side) const {
    const PcssSide& s = sides[side];
    return (lateral(q) / depth(q, side) - s.lo) / (s.hi - s.lo);
}

glm::mat4 PcssFrame::projection(int side) const {
    // Rows, each affine in q (glm is column-major: m[column][row]).
    const PcssSide& s = sides[side];
    const glm::vec3 a = axis(side);
    const glm::vec3 rx = (2.0f * eu - (s.lo.x + s.hi.x) * a) / (s.hi.x - s.lo.x);
    const glm::vec3 ry = (2.0f * ev - (s.lo.y + s.hi.y) * a) / (s.hi.y - s.lo.y);
    const glm::vec4 rows[4] = {
        glm::vec4(rx, -glm::dot(rx, center)), glm::vec4(ry, -glm::dot(ry, center)),
        glm::vec4(0.0f, 0.0f, 0.0f, zNear), glm::vec4(a, -glm::dot(a, center))};
    glm::mat4 m(0.0f);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            m[c][r] = rows[r][c];
    return m;
}

PcssFrame fitPcssFrame(const Scene& scene, std::span<const std::size_t> casterObjects,
                       const PcssFitSettings& settings) {
    return fitPcssFrame(scene, scene.light, casterObjects, settings);
}

PcssFrame fitPcssFrame(const Scene& scene, const RectLight& light,
                       std::span<const std::size_t> casterObjects,
                       const PcssFitSettings& settings) {
    PcssFrame f;
    f.center = light.center;
    f.normal = light.normal();
    f.eu = glm::normalize(light.u);
    f.ev = glm::cross(f.normal, f.eu);
    // Bounding rectangle of the light c ± u ± v in (eu, ev): (|u|, |v|) when u ⊥ v.
    f.halfSize = {std::abs(glm::dot(light.u, f.eu)) + std::abs(glm::dot(light.v, f.eu)),
                  std::abs(glm::dot(light.u, f.ev)) + std::abs(glm::dot(light.v, f.ev))};
    const Aabb bounds = scene.bounds();
    const float diagonal = bounds.empty() ? 1.0f : glm::length(bounds.extent());
    f.zNear = std::max(settings.zNearFraction * diagonal, 1e-6f);
    const float T = settings.maxTan;

    // Receivers: the box of m over every triangle's part deeper than zNear (a projective map
    // takes the clipped convex polygon to the convex hull of its vertices' images).
    const float inf = std::numeric_limits<float>::infinity();
    glm::vec2 lo[2] = {glm::vec2(inf), glm::vec2(inf)}, hi[2] = {glm::vec2(-inf), glm::vec2(-inf)};
    for (const SceneObject& o : scene.objects) {
        const MeshData& mesh = o.mesh;
        for (const glm::uvec3& tri : mesh.triangles)
            for (int side = 0; side < 2; ++side) {
                const Polygon p = clip(local(f, side, mesh.positions[tri[0]],
                                             mesh.positions[tri[1]], mesh.positions[tri[2]]),
                                       {0.0f, 0.0f, 1.0f}, -f.zNear);
                for (int i = 0; i < p.count; ++i) {
                    const glm::vec2 m = glm::vec2(p.p[i]) / p.p[i].z;
                    f.sides[side].clamped = f.sides[side].clamped ||
                                            glm::any(glm::greaterThan(glm::abs(m), glm::vec2(T)));
                    const glm::vec2 mc = glm::clamp(m, -T, T);
                    lo[side] = glm::min(lo[side], mc);
                    hi[side] = glm::max(hi[side], mc);
                    f.sides[side].present = true;
                }
            }
    }
    for (int side = 0; side < 2; ++side) {
        PcssSide& s = f.sides[side];
        if (!s.present) continue;
        // A margin of a thousandth of the extent (at least 1e-3 of the cap, so that a receiver
        // seen as a point still gets a map): receivers on the boundary keep their texels.
        const glm::vec2 pad = glm::max(1e-3f * (hi[side] - lo[side]), glm::vec2(1e-3f * T));
        s.lo = lo[side] - pad;
        s.hi = hi[side] + pad;
    }

    // Casters: the least depth of their triangles clipped to the frustum (z >= zNear and the
    // four side planes lo z <= x <= hi z, lo z <= y <= hi z).
    for (const std::size_t i : casterObjects) {
        const MeshData& mesh = scene.objects.at(i).mesh;
        for (const glm::uvec3& tri : mesh.triangles)
            for (int side = 0; side < 2; ++side) {
                PcssSide& s = f.sides[side];
                if (!s.present) continue;
                Polygon p = local(f, side, mesh.positions[tri[0]], mesh.positions[tri[1]],
                                  mesh.positions[tri[2]]);
                p = clip(p, {0.0f, 0.0f, 1.0f}, -f.zNear);
                p = clip(p, {1.0f, 0.0f, -s.lo.x}, 0.0f);
                p = clip(p, {-1.0f, 0.0f, s.hi.x}, 0.0f);
                p = clip(p, {0.0f, 1.0f, -s.lo.y}, 0.0f);
                p = clip(p, {0.0f, -1.0f, s.hi.y}, 0.0f);
                for (int k = 0; k < p.count; ++k)
                    s.casterNear =
                        s.casterNear == 0.0f ? p.p[k].z : std::min(s.casterNear, p.p[k].z);
            }
    }
    return f;
}

} // namespace geometry
