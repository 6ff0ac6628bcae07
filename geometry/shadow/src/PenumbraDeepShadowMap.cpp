#include <geometry/shadow/PenumbraDeepShadowMap.h>

#include <shared/Pdsm.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <thread>

namespace geometry {

namespace {

constexpr std::uint32_t kMaxCode = 65535u;
constexpr float kInf = std::numeric_limits<float>::infinity();

// The code at or after t: a hidden interval never starts before its depth, so that a surface
// stored at its own depth (the maps' bias is relative, 1e-3 of it) cannot hide itself where a
// code spans more than that bias (a cube face whose nearest caster lies a few tenths of a metre
// from the lamp spreads its codes thin at the far walls: 1.5 cm a code 14 m away from a caster
// 0.2 m off, against 1.4 cm of bias). Rounded to the nearest code it could start half a code
// early; no view measured so far changed by it by more than 0.0001.
std::uint32_t eventCode(float t) {
    return static_cast<std::uint32_t>(
        std::ceil(std::clamp(t, 0.0f, 1.0f) * float(kMaxCode) - 1e-3f));
}

std::uint32_t valueCode(float v) {
    return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

float decodedValue(float v) { return float(valueCode(v)) / 255.0f; }

// The stored function at code x as the lookup reads it (shared/Pdsm.h): the last point at or
// before x and the segment to the next; `left`: the limit from below x instead.
float storedAt(std::span<const PdsmPoint> p, float x, bool left) {
    if (p.empty()) return 1.0f;
    std::size_t k = 0;
    const auto before = [&](std::size_t i) {
        return left ? float(p[i].code) < x : float(p[i].code) <= x;
    };
    if (!before(0)) return decodedValue(p[0].value);
    while (k + 1 < p.size() && before(k + 1)) ++k;
    if (k + 1 == p.size()) return decodedValue(p[k].value);
    return shader::pdsmSegment(float(p[k].code), decodedValue(p[k].value), float(p[k + 1].code),
                               decodedValue(p[k + 1].value), x);
}

// The cells of a grid of `cell`-texel squares (cells [lo, hi] per axis) that the line P(t) =
// p0 + t d (texel units) crosses for t in [tA, tB], in order, each with its t-range: visit(x, y,
// ta, tb). A 2D DDA (Amanatides & Woo 1987).
template <typename Visit>
void walkCells(glm::vec2 p0, glm::vec2 d, float tA, float tB, int cell, glm::ivec2 lo,
               glm::ivec2 hi, Visit&& visit) {
    const float size = static_cast<float>(cell);
    const glm::vec2 start = p0 + d * tA;
    int c[2], step[2];
    float tNext[2], tDelta[2];
    for (int a = 0; a < 2; ++a) {
        c[a] = std::clamp(static_cast<int>(std::floor(start[a] / size)), lo[a], hi[a]);
        if (std::abs(d[a]) < 1e-12f) {
            step[a] = 0;
            tNext[a] = kInf;
            tDelta[a] = kInf;
        } else {
            step[a] = d[a] > 0.0f ? 1 : -1;
            tNext[a] = (static_cast<float>(c[a] + (d[a] > 0.0f ? 1 : 0)) * size - p0[a]) / d[a];
            tDelta[a] = size / std::abs(d[a]);
        }
    }
    float t = tA;
    const int guard = 2 * (hi[0] - lo[0] + hi[1] - lo[1]) + 8;
    for (int n = 0; t < tB && n < guard; ++n) {
        const float tExit = std::min({tNext[0], tNext[1], tB});
        if (tExit > t) visit(c[0], c[1], t, tExit);
        const int a = tNext[0] < tNext[1] ? 0 : 1;
        c[a] += step[a];
        tNext[a] += tDelta[a];
        t = tExit;
        if (c[a] < lo[a] || c[a] > hi[a]) break;
    }
}

// One map as the walk reads it: its texels and the largest stored value per block of
// kPdsmBlock^2 texels (a block whose largest value cannot hide the line there is skipped).
constexpr int kPdsmBlock = 8;
struct MapLayer {
    const float* texels;
    const float* blockMax;
    int R, blocks;
};

// A texel ray's depth as one view sees it: the view's own reversed depth s_v = near_v / z_v
// along the line through its map is affine in the walk's parameter u in [0, 1], from sNear_v
// (the deep map's t = 0; 1 where the view's near plane is the frame's) to sFar_v (t = 1); and t
// of u. For a view in the light's plane (depth 0) t = u; a view `depth` ahead of the centre
// along the map's axis sees the ray's point at centre depth z at its own z - depth, so that
// 1 / (z - depth) is affine in u, not 1 / z.
struct LineDepth {
    float sNear = 1.0f;  // the view's s at u = 0 (below 1 where its near plane is its own)
    float sFar = 0.0f;   // the view's s at u = 1
    float depth = 0.0f;  // the view's origin's depth from the centre
    float w0 = 0.0f, w1 = 0.0f; // 1 / (z - depth) at u = 0 and u = 1
    float zNear = 0.0f, gridSFar = 0.0f; // the deep map's depth code
    float t(float u) const {
        if (depth == 0.0f) return u;
        const float z = depth + 1.0f / (w0 + u * (w1 - w0));
        return (1.0f - zNear / z) / (1.0f - gridSFar);
    }
};

// Hidden intervals of u in [uLo, uHi] (within [0, 1]) along one line through one map (texel
// units, P(u) = p0 + u (p1 - p0)), as events of the deep map's depth code: code << 1 | 1 where
// one starts, code << 1 where one ends (none at the line's end, u = 1). A point of the line is
// hidden where its texel stores a value above s_v (1 + bias), s_v = sNear - u (sNear - sFar).
void walkMap(glm::vec2 p0, glm::vec2 p1, float uLo, float uHi, const MapLayer& map,
             const LineDepth& line, float bias, std::vector<std::uint32_t>& events) {
    const glm::vec2 d = p1 - p0;
    const int R = map.R;
    float tA = uLo, tB = uHi;
    const float size = static_cast<float>(R);
    for (int a = 0; a < 2; ++a) {
        if (std::abs(d[a]) < 1e-12f) {
            if (p0[a] < 0.0f || p0[a] >= size) return;
            continue;
        }
        float t0 = (0.0f - p0[a]) / d[a], t1 = (size - p0[a]) / d[a];
        if (t0 > t1) std::swap(t0, t1);
        tA = std::max(tA, t0);
        tB = std::min(tB, t1);
    }
    if (!(tA < tB)) return;
    const float depthSpan = line.sNear - line.sFar;
    // t beyond which a stored value hides the line.
    const auto hiddenFrom = [&](float stored) {
        return (line.sNear - stored / (1.0f + bias)) / depthSpan;
    };
    bool open = false;
    float openStart = 0.0f, openEnd = 0.0f;
    const auto emit = [&](float s, float e) {
        events.push_back(eventCode(line.t(s)) << 1 | 1u);
        if (e < 1.0f) events.push_back(eventCode(line.t(e)) << 1);
    };
    const auto texel = [&](int x, int y, float t, float tExit) {
        const float stored = map.texels[static_cast<std::size_t>(y) * R + x];
        if (!(stored > 0.0f)) return;
        const float h0 = std::max(t, hiddenFrom(stored));
        if (h0 >= tExit) return;
        if (open && h0 <= openEnd) {
            openEnd = tExit;
            return;
        }
        if (open) emit(openStart, openEnd);
        open = true;
        openStart = h0;
        openEnd = tExit;
    };
    const int last = map.blocks - 1;
    walkCells(p0, d, tA, tB, kPdsmBlock, glm::ivec2(0), glm::ivec2(last),
              [&](int bx, int by, float ta, float tb) {
                  // The line's s is least at tb: a block whose largest value hides nothing there
                  // hides nothing in it.
                  const float most = map.blockMax[static_cast<std::size_t>(by) * map.blocks + bx];
                  if (!(most > 0.0f) || hiddenFrom(most) >= tb) return;
                  const glm::ivec2 lo(bx * kPdsmBlock, by * kPdsmBlock);
                  const glm::ivec2 hi = glm::min(lo + (kPdsmBlock - 1), glm::ivec2(R - 1));
                  walkCells(p0, d, ta, tb, 1, lo, hi, texel);
              });
    if (open) emit(openStart, openEnd);
}

} // namespace

namespace {

// Depth t = 0 .. 1 of a deep map along `axis` from `centre`: to the farthest corner of the
// receivers' box (at least `atLeast`), a thousandth beyond, and at least 1 % beyond zNear.
float deepestReceiver(const Aabb& scene, const glm::vec3& centre, const glm::vec3& axis,
                      float atLeast, float zNear) {
    float deepest = atLeast;
    if (!scene.empty())
        for (int q = 0; q < 8; ++q)
            deepest = std::max(deepest, glm::dot(scene.corner(q) - centre, axis));
    return std::max(deepest * 1.001f, zNear * 1.01f);
}

} // namespace

glm::vec2 PdsmGrid::texelCentre(int i, int j) const {
    return lo + (glm::vec2(static_cast<float>(i), static_cast<float>(j)) + 0.5f) /
                    glm::vec2(static_cast<float>(resolution), static_cast<float>(rowCount())) *
                    (hi - lo);
}

PdsmGrid fitPdsmGrid(const SampleMapFrame& f, const glm::vec3& lightCentre, const Aabb& scene,
                     int resolution) {
    PdsmGrid g;
    g.centre = lightCentre;
    g.eu = f.eu;
    g.ev = f.ev;
    g.n = f.n;
    g.resolution = resolution;
    if (f.empty) return g;
    g.empty = false;
    g.zNear = f.zNear;
    // The deepest receiver: the scene box's farthest corner along n (at least the casters').
    const float deepest = deepestReceiver(scene, lightCentre, f.n, f.zFar, f.zNear);
    g.sFar = f.zNear / deepest;
    // inReach's widening for every depth in [zNear, deepest]: the light's half extent times
    // the spread of 1 / z, and 1 % of the casters' extent.
    const float spread = 1.0f / f.zNear - 1.0f / deepest;
    const glm::vec2 slack = 0.01f * (f.centreHi - f.centreLo) + f.half * spread;
    g.lo = f.centreLo - slack;
    g.hi = f.centreHi + slack;
    g.clipped = f.clipped;
    g.nearClipped = f.clipped; // the frame does not say whether near or beside
    for (int a = 0; a < 2; ++a) {
        if (g.lo[a] < -kSampleMapMaxTan || g.hi[a] > kSampleMapMaxTan) g.clipped = true;
        g.lo[a] = std::max(g.lo[a], -kSampleMapMaxTan);
        g.hi[a] = std::min(g.hi[a], kSampleMapMaxTan);
    }
    return g;
}

std::vector<PdsmFace> fitPdsmCube(const PcssFrame& cube, const RectLight& light,
                                  std::span<const glm::vec2> samples, const Scene& sceneObjects,
                                  std::span<const std::size_t> casterObjects, const Aabb& casters,
                                  const Aabb& scene, int resolution) {
    std::vector<PdsmFace> out;
    const glm::vec3 c = cube.center;
    const float cap = kPdsmViewCap;
    for (int k = 0; k < kPcssFaces; ++k) {
        const PcssFace& s = cube.faces[k];
        if (!s.present) continue;
        PdsmFace face;
        face.face = k;
        SampleMapFrame& f = face.frame;
        f.eu = s.b1;
        f.ev = s.b2;
        f.n = s.axis;
        float ahead = 0.0f; // the samples' greatest depth along the axis
        for (const glm::vec2& st : samples) {
            SampleMapView v;
            v.st = st;
            v.origin = light.point(st.x, st.y);
            v.depth = glm::dot(v.origin - c, s.axis);
            ahead = std::max(ahead, v.depth);
            f.views.push_back(v);
        }
        const float minNear = ahead + 0.01f * (cube.halfSize.x + cube.halfSize.y) + cube.zNear;
        const float nearest = casterNearInFrustum(cube, k, glm::vec2(-cap), glm::vec2(cap),
                                                  cube.zNear, sceneObjects, casterObjects);
        if (nearest == 0.0f) continue; // no caster within reach: lit
        f.empty = false;
        f.clipped = nearest < minNear;
        face.grid.nearClipped = f.clipped;
        f.zNear = std::max(0.999f * nearest, minNear);
        // A view behind the one furthest ahead gets a near plane as near as that one's (the
        // gap minNear - ahead, or up to the nearest caster), not the frame's zNear - depth: the
        // casters between it and the frame's zNear (a shelf under the light, seen from a side
        // face) hide receivers beyond zNear from it.
        const float ownNear = f.zNear - ahead;
        for (SampleMapView& v : f.views)
            if (f.zNear - v.depth > ownNear) v.near = ownNear;
        const float deepest = deepestReceiver(scene, c, s.axis, 0.0f, f.zNear);
        f.zFar = deepest;
        f.half = cube.halfSize;
        f.reachAll = true;
        std::array<glm::vec3, 8> box;
        for (int q = 0; q < 8; ++q) box[q] = casters.corner(q);
        for (SampleMapView& v : f.views) {
            const glm::vec3 o = v.origin - c;
            const glm::vec2 d(glm::dot(o, s.b1), glm::dot(o, s.b2));
            glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
            for (const float w : {1.0f / (f.zNear - v.depth), 1.0f / (deepest - v.depth)})
                for (int q = 0; q < 4; ++q) {
                    const glm::vec2 m((q & 1) ? s.hi.x : s.lo.x, (q & 2) ? s.hi.y : s.lo.y);
                    const glm::vec2 mv = m + (v.depth * m - d) * w;
                    lo = glm::min(lo, mv);
                    hi = glm::max(hi, mv);
                }
            // The casters' box, where it lies wholly in front of the view.
            float far = 0.0f;
            for (const glm::vec3& q : box) far = std::max(far, glm::dot(q - v.origin, s.axis));
            bool inFront = !casters.empty() && far > 0.0f;
            glm::vec2 blo(std::numeric_limits<float>::max()), bhi(-std::numeric_limits<float>::max());
            for (const glm::vec3& q : box) {
                const glm::vec3 e = q - v.origin;
                const float z = glm::dot(e, s.axis);
                if (z < kSampleMapMinDepthShare * far) {
                    inFront = false;
                    break;
                }
                const glm::vec2 mq = glm::vec2(glm::dot(e, s.b1), glm::dot(e, s.b2)) / z;
                blo = glm::min(blo, mq);
                bhi = glm::max(bhi, mq);
            }
            if (inFront && glm::all(glm::lessThan(glm::max(lo, blo), glm::min(hi, bhi)))) {
                lo = glm::max(lo, blo);
                hi = glm::min(hi, bhi);
            }
            for (int a = 0; a < 2; ++a) {
                if (lo[a] < -cap || hi[a] > cap) f.clipped = true;
                lo[a] = std::clamp(lo[a], -cap, cap);
                hi[a] = std::clamp(hi[a], -cap, cap);
                const float margin = std::max(1e-3f * (hi[a] - lo[a]), 1e-6f);
                lo[a] -= margin;
                hi[a] += margin;
            }
            v.lo = lo;
            v.hi = hi;
        }
        PdsmGrid& g = face.grid;
        g.centre = c;
        g.eu = s.b1;
        g.ev = s.b2;
        g.n = s.axis;
        // The front faces' receivers lie within the cap (faceOf gives the rest to the side
        // faces); pcss's margin beyond it is for its kernels.
        g.lo = k < 2 ? glm::max(s.lo, glm::vec2(-cube.maxTan)) : s.lo;
        g.hi = k < 2 ? glm::min(s.hi, glm::vec2(cube.maxTan)) : s.hi;
        g.resolution = resolution;
        // Texels about square in m: a side face's band a third as many rows.
        g.rows = std::clamp(static_cast<int>(std::ceil(static_cast<float>(resolution) *
                                                       (g.hi.y - g.lo.y) / (g.hi.x - g.lo.x))),
                            1, resolution);
        g.zNear = f.zNear;
        g.sFar = f.zNear / deepest;
        g.clipped = f.clipped;
        g.empty = false;
        out.push_back(std::move(face));
    }
    return out;
}

void jitterSampleMapGrids(SampleMapFrame& frame, int resolution) {
    for (std::size_t k = 0; k < frame.views.size(); ++k) {
        SampleMapView& v = frame.views[k];
        const glm::vec2 texel = (v.hi - v.lo) / static_cast<float>(resolution);
        // The R2 sequence (the plastic number's powers): well spread in the unit square.
        const float i = static_cast<float>(k);
        const glm::vec2 shift(std::fmod(0.5f + i * 0.7548776662f, 1.0f),
                              std::fmod(0.5f + i * 0.5698402910f, 1.0f));
        v.lo -= shift * texel;
        v.hi += (1.0f - shift) * texel;
    }
}

PdsmReadDepths::PdsmReadDepths(const PdsmGrid& grid, std::span<const glm::vec3> triangles,
                               float spanTexels, float offsetTexels,
                               std::span<const glm::vec3> lightCorners)
    : mGrid(grid) {
    const int R = grid.resolution, rows = grid.rowCount();
    mRows.resize(static_cast<std::size_t>(rows));
    if (grid.empty || R <= 0) return;
    mTexelU = (grid.hi.x - grid.lo.x) / static_cast<float>(R);
    mTexelV = (grid.hi.y - grid.lo.y) / static_cast<float>(rows);
    // A receiver at depth z reads no nearer than z - span, span = spanTexels texels (the
    // lookup's texel size: the larger side) times z.
    const float texelSize = std::max(mTexelU, mTexelV);
    mLowShare = std::max(1.0f - spanTexels * texelSize, 0.0f);
    // The receiver read is P moved by up to offset zP along its normal (either way).
    const float offset = std::clamp(offsetTexels * texelSize, 0.0f, 0.5f);
    mOffset = offset;
    // A receiver read nearer than zNear reads nothing (lit): the triangles clipped where even
    // the offset cannot carry them past it.
    const float zClip = grid.zNear * (1.0f - 1e-4f) / (1.0f + offset);
    const glm::vec2 texel(mTexelU, mTexelV);
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        glm::vec3 p[3];
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 e = triangles[t + k] - grid.centre;
            p[k] = glm::vec3(glm::dot(e, grid.eu), glm::dot(e, grid.ev), glm::dot(e, grid.n));
        }
        if (!std::isfinite(p[0].x + p[0].y + p[0].z + p[1].x + p[1].y + p[1].z + p[2].x +
                           p[2].y + p[2].z))
            continue;
        // Clipped to z >= zClip (Sutherland-Hodgman against one plane: at most 4 corners).
        glm::vec3 poly[4];
        int n = 0;
        for (int k = 0; k < 3; ++k) {
            const glm::vec3& a = p[k];
            const glm::vec3& b = p[(k + 1) % 3];
            const bool ina = a.z >= zClip, inb = b.z >= zClip;
            if (ina) poly[n++] = a;
            if (ina != inb) poly[n++] = a + (b - a) * ((zClip - a.z) / (b.z - a.z));
        }
        if (n < 3) continue;
        Triangle tri;
        tri.nm = glm::cross(p[1] - p[0], p[2] - p[0]);
        tri.d = glm::dot(tri.nm, p[0]);
        // The side of its plane the offset may move a receiver to: where the light lies, if
        // it lies wholly on one side (a receiver facing none of it reads nothing).
        if (!lightCorners.empty()) {
            bool above = false, below = false;
            for (const glm::vec3& corner : lightCorners) {
                const glm::vec3 e = corner - grid.centre;
                const glm::vec3 q(glm::dot(e, grid.eu), glm::dot(e, grid.ev), glm::dot(e, grid.n));
                const float side = glm::dot(tri.nm, q) - tri.d;
                above = above || side >= 0.0f;
                below = below || side <= 0.0f;
            }
            tri.towards = above && !below ? 1 : (below && !above ? -1 : 0);
        }
        tri.z0 = kInf;
        tri.z1 = 0.0f;
        glm::vec2 m0(kInf), m1(-kInf);
        float mMax = 0.0f;
        for (int k = 0; k < n; ++k) {
            tri.z0 = std::min(tri.z0, poly[k].z);
            tri.z1 = std::max(tri.z1, poly[k].z);
            const glm::vec2 m(poly[k].x / poly[k].z, poly[k].y / poly[k].z);
            m0 = glm::min(m0, m);
            m1 = glm::max(m1, m);
            mMax = std::max(mMax, glm::length(m));
        }
        // Q = P + delta N, delta <= offset zP: its m lies within delta (1 + |m|) / (zP - delta)
        // = offset (1 + |m|) / (1 - offset) of P's.
        tri.reach = offset * (1.0f + mMax) / (1.0f - offset);
        m0 -= glm::vec2(tri.reach);
        m1 += glm::vec2(tri.reach);
        // The texels whose centre lies within a texel of the box (one more for rounding),
        // clamped to the grid: a receiver past its edge reads the edge's texels in the cube.
        int lo[2], hi[2];
        const int count[2] = {R, rows};
        for (int a = 0; a < 2; ++a) {
            const float first = (m0[a] - texel[a] - grid.lo[a]) / texel[a] - 0.5f;
            const float last = (m1[a] + texel[a] - grid.lo[a]) / texel[a] - 0.5f;
            const float most = static_cast<float>(count[a] - 1);
            lo[a] = static_cast<int>(std::clamp(std::ceil(first) - 1.0f, 0.0f, most));
            hi[a] = static_cast<int>(std::clamp(std::floor(last) + 1.0f, 0.0f, most));
            tri.pastLo[a] = m0[a] < grid.lo[a] + texel[a];
            tri.pastHi[a] = m1[a] > grid.hi[a] - texel[a];
        }
        tri.i0 = lo[0];
        tri.i1 = hi[0];
        const auto index = static_cast<std::uint32_t>(mTriangles.size());
        mTriangles.push_back(tri);
        for (int j = lo[1]; j <= hi[1]; ++j) mRows[static_cast<std::size_t>(j)].push_back(index);
    }
}

void PdsmReadDepths::row(int j, std::vector<std::vector<PdsmCodeRange>>& ranges) const {
    const int R = mGrid.resolution, rows = mGrid.rowCount();
    ranges.resize(static_cast<std::size_t>(R));
    for (std::vector<PdsmCodeRange>& r : ranges) r.clear();
    if (mGrid.empty || j < 0 || j >= rows) return;
    const auto code = [&](float z, bool up) {
        const float t = std::clamp(shader::pdsmDepthCode(z, mGrid.zNear, mGrid.sFar), 0.0f, 1.0f);
        const float c = up ? std::ceil(t * float(kMaxCode)) + 2.0f
                           : std::floor(t * float(kMaxCode)) - 2.0f;
        return static_cast<std::uint32_t>(std::clamp(c, 0.0f, float(kMaxCode)));
    };
    const float v = mGrid.lo.y + (static_cast<float>(j) + 0.5f) * mTexelV;
    const bool edgeLo = j == 0, edgeHi = j == rows - 1;
    for (const std::uint32_t index : mRows[static_cast<std::size_t>(j)]) {
        const Triangle& tri = mTriangles[index];
        const bool pastRow = (edgeLo && tri.pastLo[1]) || (edgeHi && tri.pastHi[1]);
        // dot(nm, (m, 1)) over a texel's square: its centre's value +- this.
        const float reach = std::abs(tri.nm.x) * mTexelU + std::abs(tri.nm.y) * mTexelV;
        // Where a plane dot(nm, X) = d meets every ray of a square whose dot(nm, (m, 1)) spans
        // [a0, a1], its depths d / along there (extremes at the square's corners).
        const auto meets = [](float d, float a0, float a1, float& lo, float& hi) {
            if (d > 0.0f && a0 > 0.0f) {
                lo = d / a1;
                hi = d / a0;
                return true;
            }
            if (d < 0.0f && a1 < 0.0f) {
                lo = d / a0;
                hi = d / a1;
                return true;
            }
            return false;
        };
        const float wide = reach + (std::abs(tri.nm.x) + std::abs(tri.nm.y)) * tri.reach;
        const float norm = glm::length(tri.nm);
        for (int i = tri.i0; i <= tri.i1; ++i) {
            const float u = mGrid.lo.x + (static_cast<float>(i) + 0.5f) * mTexelU;
            const bool past = pastRow || (i == 0 && tri.pastLo[0]) ||
                              (i == R - 1 && tri.pastHi[0]);
            // P's depths: the triangle's, within its plane's over the square widened by the
            // offset's reach (where Q's square may hold P's).
            float pLo = tri.z0, pHi = tri.z1;
            const float along = tri.nm.x * u + tri.nm.y * v + tri.nm.z;
            float lo = 0.0f, hi = 0.0f;
            if (!past && meets(tri.d, along - wide, along + wide, lo, hi)) {
                pLo = std::max(pLo, lo);
                pHi = std::min(pHi, hi);
            }
            // Q's depths (Q = P + delta N, delta <= offset zP), read no nearer than the span.
            float zlo = pLo * (1.0f - mOffset) * mLowShare, zhi = pHi * (1.0f + mOffset);
            if (!past) {
                // Q lies on the plane moved by delta <= offset pHi (towards the light, or
                // either way), in the square: its depths there (monotone in d: the two
                // extremes) where both planes meet it.
                const float shift = mOffset * pHi * norm;
                const float dLo = tri.d - (tri.towards > 0 ? 0.0f : shift);
                const float dHi = tri.d + (tri.towards < 0 ? 0.0f : shift);
                float lo1 = 0.0f, hi1 = 0.0f, lo2 = 0.0f, hi2 = 0.0f;
                if (meets(dLo, along - reach, along + reach, lo1, hi1) &&
                    meets(dHi, along - reach, along + reach, lo2, hi2)) {
                    zlo = std::max(zlo, std::min(lo1, lo2));
                    zhi = std::min(zhi, std::max(hi1, hi2));
                }
            }
            zlo *= 1.0f - 1e-4f;
            zhi *= 1.0f + 1e-4f;
            if (!(zlo <= zhi)) continue; // the triangle reaches no receiver of this texel
            ranges[static_cast<std::size_t>(i)].push_back({code(zlo, false), code(zhi, true)});
        }
    }
    for (std::vector<PdsmCodeRange>& r : ranges) {
        if (r.size() < 2) continue;
        std::sort(r.begin(), r.end(),
                  [](const PdsmCodeRange& a, const PdsmCodeRange& b) { return a.lo < b.lo; });
        std::size_t out = 0;
        for (std::size_t k = 1; k < r.size(); ++k) {
            if (r[k].lo <= r[out].hi + kMergeGap)
                r[out].hi = std::max(r[out].hi, r[k].hi);
            else
                r[++out] = r[k];
        }
        r.resize(out + 1);
    }
}

float maskPdsmStaircase(float start, std::vector<PdsmStep>& steps,
                        std::span<const PdsmCodeRange> kept) {
    if (kept.empty()) throw std::invalid_argument("pdsm: no depths to keep");
    thread_local std::vector<PdsmStep> out;
    out.clear();
    std::size_t s = 0;
    float value = start; // the staircase's value at the code reached
    const auto reach = [&](std::uint32_t code) {
        while (s < steps.size() && steps[s].code <= code) value = steps[s++].after;
    };
    reach(kept.front().lo);
    const float first = value;
    float held = value;
    for (std::size_t r = 0; r < kept.size(); ++r) {
        if (r > 0) {
            reach(kept[r].lo);
            if (value != held) out.push_back({kept[r].lo, held, value, true});
        }
        while (s < steps.size() && steps[s].code <= kept[r].hi) {
            out.push_back(steps[s]);
            value = steps[s++].after;
        }
        held = value;
    }
    steps.assign(out.begin(), out.end());
    return first;
}

float PdsmBound::at(float v) const {
    if (!(noise > 0.0f) || samples <= 0) return tolerance;
    const float var = std::max(v * (1.0f - v), 0.0f) / static_cast<float>(samples);
    return std::max(tolerance, noise * std::sqrt(var));
}

std::vector<PdsmPoint> compressPdsmStaircase(float start, std::span<const PdsmStep> steps,
                                             const PdsmBound& bound) {
    // The values are rounded to 8 bits afterwards: at most half a step more.
    const auto epsAt = [&](float v) { return bound.at(v) - 0.5f / 255.0f - 1e-6f; };
    if (!(epsAt(0.0f) > 0.0f)) throw std::invalid_argument("pdsm: tolerance must exceed 0.5 / 255");
    if (!(bound.noise >= 0.0f) || (bound.noise > 0.0f && bound.samples <= 0))
        throw std::invalid_argument("pdsm: noise must be >= 0, with the sample count");
    std::vector<PdsmPoint> out;
    out.push_back({0u, start});
    float ox = 0.0f, oy = start;       // the current segment's start
    float slo = -kInf, shi = kInf;     // the slopes that keep every step since within eps
    float lastX = 0.0f;                // the last step taken into the window
    bool have = false;
    const auto constrain = [&](float x, float lo, float hi) {
        // Within [0, 1] too (the staircase is), so that no stored value needs clamping, which
        // would move the segment at its other steps.
        lo = std::max(lo, 0.0f);
        hi = std::min(hi, 1.0f);
        const float a = (lo - oy) / (x - ox), b = (hi - oy) / (x - ox);
        const float nlo = std::max(slo, a), nhi = std::min(shi, b);
        if (nlo > nhi) return false;
        slo = nlo;
        shi = nhi;
        lastX = x;
        have = true;
        return true;
    };
    const auto flush = [&] { // end the segment at the last step taken
        const float slope = have ? 0.5f * (slo + shi) : 0.0f;
        const float y = oy + slope * (lastX - ox);
        out.push_back({static_cast<std::uint32_t>(lastX), y});
        ox = lastX;
        oy = y;
        slo = -kInf;
        shi = kInf;
        have = false;
    };
    const auto add = [&](float x, float lo, float hi) {
        if (constrain(x, lo, hi)) return;
        flush(); // from the last step taken (before x), the window is open again
        [[maybe_unused]] const bool ok = constrain(x, lo, hi);
        assert(ok);
    };
    for (const PdsmStep& s : steps) {
        const float x = static_cast<float>(s.code);
        // The line at x within the bound of both sides of the step: the pieces before and
        // after it, each constant, deviate the most from a line at their ends.
        const float eb = epsAt(s.before), ea = epsAt(s.after);
        const float lo = std::max(s.before - eb, s.after - ea);
        const float hi = std::min(s.before + eb, s.after + ea);
        if (lo <= hi && !s.exact) {
            add(x, lo, hi);
        } else {
            // A step: the segment ends at x on `before` exactly, the next starts at `after`.
            // (Every receiver lies just before such a step, the surface it lies on, and reads
            // the value there: ending anywhere within the bound darkened every surface by up to
            // the bound, kaos2's first spawn view by 0.0026 mean at 0.008 where it has no
            // shadow.)
            add(x, s.before, s.before);
            flush();
            out.push_back({s.code, s.after});
            oy = s.after;
        }
    }
    const float last = steps.empty() ? start : steps.back().after;
    if (steps.empty() || steps.back().code < kMaxCode)
        add(static_cast<float>(kMaxCode), last - epsAt(last), last + epsAt(last));
    if (have) flush();
    // A constant function needs its first point only.
    bool constant = true;
    for (const PdsmPoint& p : out) constant = constant && valueCode(p.value) == valueCode(start);
    if (constant) out.resize(1);
    for (PdsmPoint& p : out) p.value = decodedValue(p.value);
    return out;
}

namespace {

// One walk over the staircase's pieces: the largest |stored - staircase| and the largest
// |stored - staircase| - bound.at(staircase) (exact: both are linear or constant between the
// steps and the points, which lie on the steps' codes).
struct PdsmFit {
    float deviation = 0.0f;
    float excess = -kInf;
};

PdsmFit pdsmFit(float start, std::span<const PdsmStep> steps, std::span<const PdsmPoint> points,
                const PdsmBound& bound) {
    PdsmFit fit;
    float c = 0.0f, f = start;
    const auto piece = [&](float next, bool end) {
        const float b = bound.at(f);
        for (const float d : {std::abs(storedAt(points, c, false) - f),
                              std::abs(storedAt(points, next, !end) - f)}) {
            fit.deviation = std::max(fit.deviation, d);
            fit.excess = std::max(fit.excess, d - b);
        }
    };
    for (const PdsmStep& s : steps) {
        piece(static_cast<float>(s.code), false);
        c = static_cast<float>(s.code);
        f = s.after;
    }
    piece(static_cast<float>(kMaxCode), true);
    return fit;
}

} // namespace

float pdsmDeviation(float start, std::span<const PdsmStep> steps,
                    std::span<const PdsmPoint> points) {
    return pdsmFit(start, steps, points, PdsmBound{}).deviation;
}

float pdsmExcess(float start, std::span<const PdsmStep> steps, std::span<const PdsmPoint> points,
                 const PdsmBound& bound) {
    return pdsmFit(start, steps, points, bound).excess;
}

namespace {

// Per layer, the largest stored value of each kPdsmBlock^2 block.
std::vector<float> blockMaxima(const PdsmMaps& maps, std::size_t layers, int& blocks) {
    const int R = maps.resolution;
    blocks = (R + kPdsmBlock - 1) / kPdsmBlock;
    const std::size_t per = static_cast<std::size_t>(blocks) * static_cast<std::size_t>(blocks);
    std::vector<float> out(per * layers, 0.0f);
    for (std::size_t k = 0; k < layers; ++k) {
        const float* layer = maps.texels.data() + k * static_cast<std::size_t>(R) * R;
        float* b = out.data() + k * per;
        for (int y = 0; y < R; ++y)
            for (int x = 0; x < R; ++x) {
                float& m = b[static_cast<std::size_t>(y / kPdsmBlock) * blocks + x / kPdsmBlock];
                m = std::max(m, layer[static_cast<std::size_t>(y) * R + x]);
            }
    }
    return out;
}

// Texel (i, j)'s staircase, exact within the depth codes `kept` (sorted, disjoint; empty: every
// depth): each map's line is walked over those depths only, and the staircase's value between
// them is not the texel's (maskPdsmStaircase replaces it).
float staircase(const SampleMapFrame& frame, const PdsmGrid& grid, const PdsmMaps& maps,
                const std::vector<float>& blockMax, int blocks, int i, int j, float depthBias,
                std::span<const PdsmCodeRange> kept, std::vector<PdsmStep>& steps) {
    thread_local std::vector<std::uint32_t> events;
    events.clear();
    steps.clear();
    const int R = maps.resolution;
    const std::size_t layerSize = static_cast<std::size_t>(R) * static_cast<std::size_t>(R);
    const std::size_t blockSize =
        static_cast<std::size_t>(blocks) * static_cast<std::size_t>(blocks);
    const glm::vec2 m = grid.texelCentre(i, j);
    const float size = static_cast<float>(R);
    for (std::size_t k = 0; k < frame.views.size(); ++k) {
        const SampleMapView& v = frame.views[k];
        const glm::vec3 o = v.origin - grid.centre;
        const glm::vec2 d(glm::dot(o, grid.eu), glm::dot(o, grid.ev));
        const glm::vec2 inv = 1.0f / (v.hi - v.lo);
        LineDepth line;
        glm::vec2 p0, p1;
        // The view's reversed depth s = near / z from its near plane (zNear - depth unless its
        // own, SampleMapView::near).
        const float near = frame.viewNear(k);
        if (v.depth == 0.0f) {
            // m - d s / zNear in map k, at s = 1 (t = 0) and s = sFar (t = 1), in texels.
            p0 = (m - d / grid.zNear - v.lo) * inv * size;
            p1 = (m - d * (grid.sFar / grid.zNear) - v.lo) * inv * size;
            line.sNear = near / grid.zNear;
            line.sFar = near * grid.sFar / grid.zNear;
        } else {
            // From the view, the ray's point at centre depth z lies at m + (depth m - d) w,
            // w = 1 / (z - depth): affine in w, from zNear (t = 0) to zNear / sFar (t = 1).
            line.depth = v.depth;
            line.w0 = 1.0f / (grid.zNear - v.depth);
            line.w1 = 1.0f / (grid.zNear / grid.sFar - v.depth);
            line.zNear = grid.zNear;
            line.gridSFar = grid.sFar;
            // s = near w.
            line.sNear = near * line.w0;
            line.sFar = near * line.w1;
            p0 = (m + (v.depth * m - d) * line.w0 - v.lo) * inv * size;
            p1 = (m + (v.depth * m - d) * line.w1 - v.lo) * inv * size;
        }
        // u of a depth code (line.t's inverse), a code further out for the codes' rounding.
        const auto uOf = [&](std::uint32_t code, int out) {
            const float t = std::clamp(static_cast<float>(static_cast<int>(code) + out) /
                                           float(kMaxCode),
                                       0.0f, 1.0f);
            if (v.depth == 0.0f) return t;
            const float z = grid.zNear / (1.0f - t * (1.0f - grid.sFar));
            const float w = 1.0f / (z - v.depth);
            return std::clamp((w - line.w0) / (line.w1 - line.w0), 0.0f, 1.0f);
        };
        const MapLayer layer{maps.texels.data() + k * layerSize, blockMax.data() + k * blockSize,
                             R, blocks};
        if (kept.empty()) {
            walkMap(p0, p1, 0.0f, 1.0f, layer, line, depthBias, events);
        } else {
            for (const PdsmCodeRange& r : kept)
                walkMap(p0, p1, uOf(r.lo, -1), uOf(r.hi, 1), layer, line, depthBias, events);
        }
    }
    std::sort(events.begin(), events.end());
    const float n = static_cast<float>(frame.views.size());
    int hidden = 0;
    std::size_t e = 0;
    while (e < events.size() && (events[e] >> 1) == 0u) hidden += (events[e++] & 1u) ? 1 : -1;
    const float start = 1.0f - static_cast<float>(hidden) / n;
    while (e < events.size()) {
        const std::uint32_t code = events[e] >> 1;
        const float before = 1.0f - static_cast<float>(hidden) / n;
        while (e < events.size() && (events[e] >> 1) == code)
            hidden += (events[e++] & 1u) ? 1 : -1;
        const float after = 1.0f - static_cast<float>(hidden) / n;
        if (after != before) steps.push_back({code, before, after});
    }
    return start;
}

} // namespace

Pdsm buildPdsm(const SampleMapFrame& frame, const PdsmGrid& grid, const PdsmMaps& maps,
               const PdsmBuildSettings& settings) {
    const auto t0 = std::chrono::steady_clock::now();
    Pdsm out;
    out.grid = grid;
    const int R = grid.resolution, rows = grid.rowCount();
    const std::size_t texels = static_cast<std::size_t>(R) * static_cast<std::size_t>(rows);
    out.index.assign(2 * texels, 0u);
    if (grid.empty || frame.views.empty()) return out;
    const std::size_t layer =
        static_cast<std::size_t>(maps.resolution) * static_cast<std::size_t>(maps.resolution);
    if (maps.texels.size() < layer * frame.views.size())
        throw std::invalid_argument("pdsm: fewer map texels than the frame's views need");

    int blocks = 0;
    const std::vector<float> blockMax = blockMaxima(maps, frame.views.size(), blocks);
    // Per row: its texels' packed points, and each texel's count.
    std::vector<std::vector<std::uint32_t>> rowPoints(static_cast<std::size_t>(rows));
    struct Partial {
        PdsmStats stats;
    };
    int threads = settings.threads > 0 ? settings.threads
                                       : static_cast<int>(std::thread::hardware_concurrency());
    threads = std::clamp(threads, 1, 64);
    std::vector<Partial> partial(static_cast<std::size_t>(threads));
    std::atomic<int> nextRow{0}, rowsDone{0};
    const PdsmBound bound{.tolerance = settings.tolerance,
                          .noise = settings.noise,
                          .samples = static_cast<int>(frame.views.size())};
    std::optional<PdsmReadDepths> reads;
    if (settings.receivers)
        reads.emplace(grid, *settings.receivers, settings.readSpanTexels,
                      settings.readOffsetTexels, settings.lightCorners);
    const auto work = [&](int w) {
        std::vector<PdsmStep> steps;
        std::vector<std::vector<PdsmCodeRange>> ranges;
        PdsmStats& st = partial[static_cast<std::size_t>(w)].stats;
        for (int j = nextRow++; j < rows; j = nextRow++) {
            std::vector<std::uint32_t>& row = rowPoints[static_cast<std::size_t>(j)];
            if (reads) reads->row(j, ranges);
            for (int i = 0; i < R; ++i) {
                std::uint32_t count = 0;
                float start = 1.0f;
                if (reads) {
                    // Only the depths a receiver may read (none: the texel is not walked).
                    const std::vector<PdsmCodeRange>& kept = ranges[static_cast<std::size_t>(i)];
                    if (kept.empty()) continue; // index: count 0, lit
                    for (const PdsmCodeRange& r : kept) st.codesKept += r.hi - r.lo + 1;
                    start = staircase(frame, grid, maps, blockMax, blocks, i, j,
                                      settings.depthBias, kept, steps);
                    start = maskPdsmStaircase(start, steps, kept);
                } else {
                    st.codesKept += kMaxCode + 1;
                    start = staircase(frame, grid, maps, blockMax, blocks, i, j,
                                      settings.depthBias, {}, steps);
                }
                ++st.texelsRead;
                if (!(steps.empty() && valueCode(start) == 255u)) {
                    const std::vector<PdsmPoint> pts = compressPdsmStaircase(start, steps, bound);
                    const PdsmFit fit = pdsmFit(start, steps, pts, bound);
                    st.maxDeviation = std::max(st.maxDeviation, fit.deviation);
                    st.maxExcess = std::max(st.maxExcess, fit.excess);
                    for (const PdsmPoint& p : pts) row.push_back(p.code | valueCode(p.value) << 16);
                    count = static_cast<std::uint32_t>(pts.size());
                    ++st.texelsStored;
                    st.longest = std::max(st.longest, count);
                    st.points += count;
                    st.steps += steps.size();
                }
                out.index[2 * (static_cast<std::size_t>(j) * R + i) + 1] = count;
            }
            const int done = ++rowsDone;
            if (w == 0 && settings.progress) settings.progress(done, rows);
        }
    };
    std::vector<std::thread> pool;
    for (int w = 1; w < threads; ++w) pool.emplace_back(work, w);
    try {
        work(0); // the progress callback may throw (an interrupted bench): stop the others
    } catch (...) {
        nextRow = rows;
        for (std::thread& t : pool) t.join();
        throw;
    }
    for (std::thread& t : pool) t.join();
    if (settings.progress) settings.progress(rows, rows);

    for (const Partial& p : partial) {
        out.stats.points += p.stats.points;
        out.stats.steps += p.stats.steps;
        out.stats.texelsStored += p.stats.texelsStored;
        out.stats.texelsRead += p.stats.texelsRead;
        out.stats.codesKept += p.stats.codesKept;
        out.stats.longest = std::max(out.stats.longest, p.stats.longest);
        out.stats.maxDeviation = std::max(out.stats.maxDeviation, p.stats.maxDeviation);
        out.stats.maxExcess = std::max(out.stats.maxExcess, p.stats.maxExcess);
    }
    if (out.stats.points > 0xFFFFFFFFull)
        throw std::length_error("pdsm: more than 2^32 points");
    // Concatenate in texel order, each texel's points from a group's start.
    std::uint64_t groups = 0;
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < R; ++i)
            groups += (out.index[2 * (static_cast<std::size_t>(j) * R + i) + 1] + 3) / 4;
    if (groups > 0xFFFFFFFFull) throw std::length_error("pdsm: more than 2^32 point groups");
    out.data.assign(3 * groups, 0u);
    std::uint32_t group = 0;
    for (int j = 0; j < rows; ++j)
        group = packPdsmRow(rowPoints[static_cast<std::size_t>(j)],
                            out.index.data() + 2 * static_cast<std::size_t>(j) * R, R,
                            0xFFFFFFFFu, group, out.data.data());
    out.stats.buildMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

std::uint32_t packPdsmRow(std::span<const std::uint32_t> points, std::uint32_t* index, int texels,
                          std::uint32_t countMask, std::uint32_t group, std::uint32_t* data) {
    std::size_t r = 0;
    for (int i = 0; i < texels; ++i) {
        const std::uint32_t count = index[2 * i + 1] & countMask;
        index[2 * i] = group;
        packPdsmPoints(points.subspan(r, count), data + 3 * static_cast<std::size_t>(group));
        r += count;
        group += (count + 3) / 4;
    }
    return group;
}

void packPdsmPoints(std::span<const std::uint32_t> points, std::uint32_t* words) {
    for (std::size_t p = 0; p < points.size(); ++p) {
        const std::uint32_t bits = points[p] & 0xFFFFFFu;
        std::uint32_t* w = words + 3 * (p / 4);
        switch (p % 4) {
        case 0: w[0] |= bits; break;
        case 1:
            w[0] |= bits << 24;
            w[1] |= bits >> 8;
            break;
        case 2:
            w[1] |= bits << 16;
            w[2] |= bits >> 16;
            break;
        default: w[2] |= bits << 8; break;
        }
    }
}

float evaluatePdsmFunction(std::span<const std::uint32_t> data, std::uint32_t first,
                           std::uint32_t count, float t) {
    // The lookup's statements (shaders/lib/Pdsm.glsl pdsmFunction), a group of four points per
    // read.
    if (count == 0) return 1.0f;
    const auto group = [&](std::uint32_t g) {
        const std::uint32_t* w = data.data() + 3 * static_cast<std::size_t>(first + g);
        return glm::uvec3(w[0], w[1], w[2]);
    };
    // The last group whose first point lies at or before t (the first group if none does):
    // the first pass reads group 0, each later one the middle of what is left.
    std::uint32_t lo = 0, hi = (count - 1) / 4, at = 0;
    glm::uvec3 w(0u);
    for (;;) {
        const glm::uvec3 m = group(at);
        if (at == 0 || shader::pdsmPointDepth(shader::pdsmPointBits(m.x, m.y, m.z, 0u)) <= t) {
            lo = at;
            w = m;
        } else {
            hi = at - 1;
        }
        if (lo >= hi) break;
        at = (lo + hi + 1) >> 1;
    }
    const std::uint32_t inGroup = std::min(count - 4 * lo, 4u);
    const std::uint32_t next = lo + 1 < (count + 3) / 4 ? lo + 1 : lo;
    const glm::uvec3 wn = group(next);
    return shader::pdsmGroupValue(w.x, w.y, w.z, inGroup, wn.x, wn.y, wn.z, next != lo, t);
}

float evaluatePdsm(const Pdsm& map, int i, int j, float t) {
    const std::size_t at = 2 * (static_cast<std::size_t>(j) * map.grid.resolution + i);
    return evaluatePdsmFunction(map.data, map.index[at], map.index[at + 1], t);
}

} // namespace geometry
