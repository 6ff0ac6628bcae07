// The PCSS shadow maps' frame (geometry/shadow/PcssFrame.h).
#include <geometry/shadow/PcssFrame.h>

#include <geometry/scene/AlphaMask.h>

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

// The triangle in a face's local coordinates (x, y, z): lateral, then depth.
Polygon local(const PcssFrame& f, int face, const glm::vec3& a, const glm::vec3& b,
              const glm::vec3& c) {
    Polygon t;
    for (const glm::vec3& q : {a, b, c})
        t.p[t.count++] = f.local(q, face);
    return t;
}

// The part of a local polygon inside a face's frustum: z >= zNear and lo z <= (x, y) <= hi z.
Polygon clipToFrustum(Polygon p, const PcssFace& s, float zNear) {
    p = clip(p, {0.0f, 0.0f, 1.0f}, -zNear);
    p = clip(p, {1.0f, 0.0f, -s.lo.x}, 0.0f);
    p = clip(p, {-1.0f, 0.0f, s.hi.x}, 0.0f);
    p = clip(p, {0.0f, 1.0f, -s.lo.y}, 0.0f);
    p = clip(p, {0.0f, -1.0f, s.hi.y}, 0.0f);
    return p;
}

glm::vec3 inFace(const PcssFace& s, const glm::vec3& w) {
    return {glm::dot(w, s.b1), glm::dot(w, s.b2), glm::dot(w, s.axis)};
}

} // namespace

int PcssFrame::faceOf(const glm::vec3& q) const {
    const glm::vec3 d = q - center;
    const float x = glm::dot(d, eu), y = glm::dot(d, ev), z = glm::dot(d, normal);
    const float a = std::max(std::abs(x), std::abs(y));
    if (a <= maxTan * std::abs(z)) return std::abs(z) > zNear ? (z > 0.0f ? 0 : 1) : -1;
    if (a <= zNear) return -1;
    if (std::abs(x) >= std::abs(y)) return x >= 0.0f ? 2 : 3;
    return y >= 0.0f ? 4 : 5;
}

glm::vec2 PcssFrame::textureCoord(const glm::vec3& q, int face) const {
    const PcssFace& s = faces[face];
    return (lateral(q, face) / depth(q, face) - s.lo) / (s.hi - s.lo);
}

glm::mat4 PcssFrame::projection(int face) const {
    // Rows, each affine in q (glm is column-major: m[column][row]).
    const PcssFace& s = faces[face];
    const glm::vec3 a = s.axis;
    const glm::vec3 rx = (2.0f * s.b1 - (s.lo.x + s.hi.x) * a) / (s.hi.x - s.lo.x);
    const glm::vec3 ry = (2.0f * s.b2 - (s.lo.y + s.hi.y) * a) / (s.hi.y - s.lo.y);
    const glm::vec4 rows[4] = {
        glm::vec4(rx, -glm::dot(rx, center)), glm::vec4(ry, -glm::dot(ry, center)),
        glm::vec4(0.0f, 0.0f, 0.0f, zNear), glm::vec4(a, -glm::dot(a, center))};
    glm::mat4 m(0.0f);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            m[c][r] = rows[r][c];
    return m;
}

glm::vec3 PcssFrame::lightU(int face) const { return inFace(faces[face], halfSize.x * eu); }
glm::vec3 PcssFrame::lightV(int face) const { return inFace(faces[face], halfSize.y * ev); }

glm::vec2 throughLight(const glm::vec3& p, const glm::vec3& l, float z) {
    const float t = glm::clamp((p.z - z) / (p.z - l.z), 0.0f, 1.0f);
    const glm::vec3 q = p + t * (l - p);
    return glm::vec2(q) / q.z;
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
    f.maxTan = T;
    const glm::vec3 axes[kPcssFaces][3] = {
        {f.normal, f.eu, f.ev}, {-f.normal, f.eu, f.ev}, {f.eu, f.ev, f.normal},
        {-f.eu, f.ev, f.normal}, {f.ev, f.eu, f.normal}, {-f.ev, f.eu, f.normal}};
    for (int k = 0; k < kPcssFaces; ++k) {
        f.faces[k].axis = axes[k][0];
        f.faces[k].b1 = axes[k][1];
        f.faces[k].b2 = axes[k][2];
    }
    // The side faces' fixed extents (faceOf: beyond the front faces' cap, |z| / |x| < 1 / T),
    // with a margin of a thousandth.
    for (int k = 2; k < kPcssFaces; ++k) {
        const glm::vec2 half(1.0f, 1.0f / T);
        f.faces[k].lo = -1.001f * half;
        f.faces[k].hi = 1.001f * half;
    }

    // Receivers: the front faces' box of m over every triangle's part deeper than zNear (a
    // projective map takes the clipped convex polygon to the convex hull of its vertices'
    // images), clamped to the cap; a side face is present when a triangle reaches its frustum.
    const float inf = std::numeric_limits<float>::infinity();
    glm::vec2 lo[2] = {glm::vec2(inf), glm::vec2(inf)}, hi[2] = {glm::vec2(-inf), glm::vec2(-inf)};
    for (const SceneObject& o : scene.objects) {
        const MeshData& mesh = o.mesh;
        for (const glm::uvec3& tri : mesh.triangles) {
            const glm::vec3& a = mesh.positions[tri[0]];
            const glm::vec3& b = mesh.positions[tri[1]];
            const glm::vec3& c = mesh.positions[tri[2]];
            for (int side = 0; side < 2; ++side) {
                PcssFace& s = f.faces[side];
                const Polygon p = clip(local(f, side, a, b, c), {0.0f, 0.0f, 1.0f}, -f.zNear);
                for (int i = 0; i < p.count; ++i) {
                    const glm::vec2 m = glm::vec2(p.p[i]) / p.p[i].z;
                    s.clamped = s.clamped || glm::any(glm::greaterThan(glm::abs(m), glm::vec2(T)));
                    const glm::vec2 mc = glm::clamp(m, -T, T);
                    lo[side] = glm::min(lo[side], mc);
                    hi[side] = glm::max(hi[side], mc);
                    s.present = true;
                }
            }
            for (int k = 2; k < kPcssFaces; ++k)
                if (!f.faces[k].present)
                    f.faces[k].present =
                        clipToFrustum(local(f, k, a, b, c), f.faces[k], f.zNear).count > 0;
        }
    }
    for (int side = 0; side < 2; ++side) {
        PcssFace& s = f.faces[side];
        if (!s.present) continue;
        // A margin of a thousandth of the extent (at least 1e-3 of the cap, so that a receiver
        // seen as a point still gets a map): receivers on the boundary keep their texels.
        const glm::vec2 pad = glm::max(1e-3f * (hi[side] - lo[side]), glm::vec2(1e-3f * T));
        s.lo = lo[side] - pad;
        s.hi = hi[side] + pad;
    }

    // A front face without receivers still holds the casters its neighbours' kernels reach:
    // its whole cap.
    for (int side = 0; side < 2; ++side)
        if (!f.faces[side].present) {
            f.faces[side].lo = glm::vec2(-T);
            f.faces[side].hi = glm::vec2(T);
        }

    // Casters: the least depth of their triangles clipped to each face's frustum.
    for (const std::size_t i : casterObjects) {
        const MeshData& mesh = scene.objects.at(i).mesh;
        for (const glm::uvec3& tri : mesh.triangles)
            for (int k = 0; k < kPcssFaces; ++k) {
                PcssFace& s = f.faces[k];
                const Polygon p = clipToFrustum(local(f, k, mesh.positions[tri[0]],
                                                      mesh.positions[tri[1]],
                                                      mesh.positions[tri[2]]),
                                                s, f.zNear);
                for (int v = 0; v < p.count; ++v)
                    s.casterNear =
                        s.casterNear == 0.0f ? p.p[v].z : std::min(s.casterNear, p.p[v].z);
            }
    }
    // Drawn: casters in the face, and receivers in it or in a face beside it (a kernel near a
    // face's edge reads on in the next face).
    for (int k = 0; k < kPcssFaces; ++k) {
        bool neighbour = false;
        for (int j = 0; j < kPcssFaces; ++j)
            neighbour = neighbour || (f.faces[j].present && j != k && (j ^ 1) != k);
        f.faces[k].drawn = f.faces[k].casterNear > 0.0f && (f.faces[k].present || neighbour);
    }
    return f;
}

float casterNearInFrustum(const PcssFrame& f, int face, glm::vec2 lo, glm::vec2 hi, float zMin,
                          const Scene& scene, std::span<const std::size_t> objects) {
    PcssFace s = f.faces[face];
    s.lo = lo;
    s.hi = hi;
    float nearest = 0.0f;
    for (const std::size_t i : objects) {
        const MeshData& mesh = scene.objects.at(i).mesh;
        for (const glm::uvec3& tri : mesh.triangles) {
            const Polygon p = clipToFrustum(local(f, face, mesh.positions[tri[0]],
                                                  mesh.positions[tri[1]], mesh.positions[tri[2]]),
                                            s, zMin);
            for (int v = 0; v < p.count; ++v)
                nearest = nearest == 0.0f ? p.p[v].z : std::min(nearest, p.p[v].z);
        }
    }
    return nearest;
}

namespace {

struct ClusterTriangle {
    Aabb box;
    glm::vec3 centre;
};

void splitClusters(std::vector<ClusterTriangle>& t, std::size_t begin, std::size_t end,
                   int boxes, std::vector<Aabb>& out) {
    Aabb all;
    for (std::size_t i = begin; i < end; ++i) all.extend(t[i].box);
    if (boxes <= 1 || end - begin <= 1) {
        out.push_back(all);
        return;
    }
    Aabb centres;
    for (std::size_t i = begin; i < end; ++i) centres.extend(t[i].centre);
    const glm::vec3 extent = centres.max - centres.min;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const std::size_t mid = begin + (end - begin) / 2;
    std::nth_element(t.begin() + static_cast<std::ptrdiff_t>(begin),
                     t.begin() + static_cast<std::ptrdiff_t>(mid),
                     t.begin() + static_cast<std::ptrdiff_t>(end),
                     [axis](const ClusterTriangle& a, const ClusterTriangle& b) {
                         return a.centre[axis] < b.centre[axis];
                     });
    splitClusters(t, begin, mid, boxes / 2, out);
    splitClusters(t, mid, end, boxes - boxes / 2, out);
}

} // namespace

std::vector<Aabb> casterClusters(const Scene& scene, std::span<const std::size_t> objects,
                                 int maxBoxes, AlphaRule rule) {
    std::vector<ClusterTriangle> t;
    for (const std::size_t o : objects) {
        const MeshData& m = scene.objects[o].mesh;
        for (std::uint32_t i = 0; i < m.triangles.size(); ++i) {
            ClusterTriangle c;
            c.box = occlusionBounds(m, i, rule);
            if (c.box.empty()) continue; // cut out wholly: hides no light
            c.centre = 0.5f * (c.box.min + c.box.max);
            t.push_back(c);
        }
    }
    std::vector<Aabb> out;
    if (t.empty() || maxBoxes < 1) return out;
    splitClusters(t, 0, t.size(), maxBoxes, out);
    return out;
}

bool sweepMeetsBox(const Aabb& from, const glm::vec3& to, const Aabb& box) {
    if (from.empty() || box.empty()) return false;
    float lo = 0.0f, hi = 1.0f;
    // a + s d <= m (below = true) or >= m, for s in [lo, hi].
    auto clip = [&](float a, float d, float m, bool below) {
        const float slack = below ? m - a : a - m; // needs s d <= slack (below), -s d <= slack
        const float rate = below ? d : -d;
        if (rate == 0.0f) {
            if (slack < 0.0f) hi = -1.0f;
        } else if (rate > 0.0f) {
            hi = std::min(hi, slack / rate);
        } else {
            lo = std::max(lo, slack / rate);
        }
    };
    for (int i = 0; i < 3; ++i) {
        clip(from.min[i], to[i] - from.min[i], box.max[i], true);  // the swept box's low side
        clip(from.max[i], to[i] - from.max[i], box.min[i], false); // its high side
    }
    return lo <= hi;
}

} // namespace geometry
