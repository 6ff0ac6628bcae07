// Float edge coverage (geometry/Coverage.h). Twin of shaders/lib/Coverage.glsl: every statement
// below has its counterpart there, in the same order and with the same names; only the C++
// spelling differs (0.0f, references for inout).
#include <geometry/Coverage.h>

#include "CoverageDetail.h"

#include <cmath>

namespace geometry {
namespace {

using glm::vec2;
using glm::vec3;
using std::abs;
using std::max;
using std::min;

} // namespace

// The helpers are shared with the per-part twin (Parts.cpp), as Parts.glsl uses Coverage.glsl's.
namespace coverage_detail {

float coverageCross2(vec2 a, vec2 b) {
    return a.x * b.y - a.y * b.x;
}

// Restricts [lo, hi] to the l where f0 + l (f1 - f0) <= 0; false when that leaves nothing.
bool coverageClipLe0(float f0, float f1, float& lo, float& hi) {
    if (f0 <= 0.0f && f1 <= 0.0f) return lo <= hi;
    if (f0 > 0.0f && f1 > 0.0f) return false;
    const float l = f0 / (f0 - f1);
    if (f0 > 0.0f)
        lo = max(lo, l);
    else
        hi = min(hi, l);
    return lo <= hi;
}

// Restricts [lo, hi] to the l where a + l (b - a) lies in the half-plane dot(h, (x, y, 1)) >= 0
// (closed, like the polygon clipping of the double version); false when that leaves nothing.
bool coverageClipHalf(vec3 h, vec2 a, vec2 b, float& lo, float& hi) {
    return coverageClipLe0(-dot(h, vec3(a, 1.0f)), -dot(h, vec3(b, 1.0f)), lo, hi);
}

// Twice the area of R (edgeCoverage) is the sum of cross(start, end) over the pieces of its
// boundary (Green, the centre as origin). One piece: a + l (b - a), l in [lo, hi], between the
// rays h0, h1.
float coverageSegment(vec2 a, vec2 b, float lo, float hi, vec3 h0, vec3 h1) {
    if (!coverageClipHalf(h0, a, b, lo, hi)) return 0.0f;
    if (!coverageClipHalf(h1, a, b, lo, hi)) return 0.0f;
    return coverageCross2(a + lo * (b - a), a + hi * (b - a));
}

// The piece of R's boundary along the light square's edge a -> b (counter-clockwise), where fa,
// fb are the line's h2 at a and b (R: h2 >= 0). Where the edge crosses the line, the crossing is
// kept as the start (leave) or end (enter) of the boundary's piece along the line: computed once
// for both pieces, so that they meet exactly however obliquely the line crosses the edge.
float coverageSquareEdge(vec2 a, vec2 b, float fa, float fb, vec3 h0, vec3 h1, vec2& leave,
                         vec2& enter) {
    if (fa < 0.0f && fb < 0.0f) return 0.0f;
    float lo = 0.0f;
    float hi = 1.0f;
    if (fa < 0.0f || fb < 0.0f) {
        const float l = fa / (fa - fb);
        const vec2 x = a + l * (b - a);
        if (fa >= 0.0f) {
            leave = x;
            hi = l;
        } else {
            enter = x;
            lo = l;
        }
    }
    return coverageSegment(a, b, lo, hi, h0, h1);
}

// The edge point at parameter l, projected from p onto the light's plane, in homogeneous light
// coordinates (s, t, w) (w = 0: at infinity). With x the edge point, z its height over p's
// height and w = 1 - z, the projection is y = x - z p - (1 - z) c, computed as (x - c) - z (p - c)
// when x is nearer the light's plane (z < 1/2) and as (x - p) + w (p - c) when nearer p's level:
// each form adds a small multiple of p - c to a short vector, so neither cancels (k: end points
// relative to c, d: relative to p).
vec3 coverageProject(float l, vec3 k0, vec3 k1, vec3 d0, vec3 d1, float z0, float z1, float w0,
                     float w1, vec3 pc, const CoverageLight& light) {
    const float z = z0 + l * (z1 - z0);
    const float w = max(0.0f, w0 + l * (w1 - w0)); // rounding must not flip a point at infinity
    const vec3 y = z < 0.5f ? (k0 + l * (k1 - k0)) - z * pc : (d0 + l * (d1 - d0)) + w * pc;
    return vec3(dot(light.uStar, y), dot(light.vStar, y), w);
}

} // namespace coverage_detail

using namespace coverage_detail;

CoverageLight coverageLight(vec3 c, vec3 u, vec3 v) {
    CoverageLight light;
    light.c = c;
    light.u = u;
    light.v = v;
    light.n = normalize(cross(u, v));
    const vec3 a = cross(v, light.n);
    const vec3 b = cross(light.n, u);
    light.uStar = a / dot(u, a);
    light.vStar = b / dot(v, b);
    return light;
}

float edgeCoverage(vec3 p, vec3 e0, vec3 e1, const CoverageLight& light) {
    const vec3 pc = p - light.c;
    const vec3 k0 = e0 - light.c;
    const vec3 k1 = e1 - light.c;
    const vec3 d0 = e0 - p;
    const vec3 d1 = e1 - p;
    const float hp = dot(light.n, pc);
    if (!(abs(hp) > 0.0f)) return 0.0f; // on the light's plane: nothing in between
    // Heights over p's height (z) and depths below p's level (w = 1 - z), each from its own
    // accurate difference.
    const float z0 = dot(light.n, k0) / hp;
    const float z1 = dot(light.n, k1) / hp;
    const float w0 = -dot(light.n, d0) / hp;
    const float w1 = -dot(light.n, d1) / hp;
    // Only the part of the edge strictly between p's level and the light's plane can block.
    float lo = 0.0f;
    float hi = 1.0f;
    if (!coverageClipLe0(-z0, -z1, lo, hi)) return 0.0f;
    if (!coverageClipLe0(-w0, -w1, lo, hi)) return 0.0f;
    const vec3 q0 = coverageProject(lo, k0, k1, d0, d1, z0, z1, w0, w1, pc, light);
    const vec3 q1 = coverageProject(hi, k0, k1, d0, d1, z0, z1, w0, w1, pc, light);
    const float cr = q0.x * q1.y - q0.y * q1.x;
    if (cr == 0.0f) return 0.0f; // projected edge through the centre (or empty)
    const float sg = cr > 0.0f ? 1.0f : -1.0f;
    const vec3 line = cross(q0, q1); // homogeneous line through q0, q1
    // R: the light points beyond q0 q1 from the centre, between the rays to q0 and q1; the
    // half-planes dot(h, (x, y, 1)) >= 0 bounding it.
    const vec3 h0 = vec3(-sg * q0.y, sg * q0.x, 0.0f); // left of the ray to q0
    const vec3 h1 = vec3(sg * q1.y, -sg * q1.x, 0.0f); // right of the ray to q1
    const vec3 h2 = -sg * line;                        // beyond q0 q1 from the centre
    // h2 at the light's corners (s, t) = (-1, -1), (1, -1), (1, 1), (-1, 1), counter-clockwise;
    // all negative: the light is wholly on the centre's side of the line.
    const float f0 = dot(h2, vec3(-1.0f, -1.0f, 1.0f));
    const float f1 = dot(h2, vec3(1.0f, -1.0f, 1.0f));
    const float f2 = dot(h2, vec3(1.0f, 1.0f, 1.0f));
    const float f3 = dot(h2, vec3(-1.0f, 1.0f, 1.0f));
    if (f0 < 0.0f && f1 < 0.0f && f2 < 0.0f && f3 < 0.0f) return 0.0f;
    // The area of R integrated along its boundary, counter-clockwise, without building the
    // polygon (arrays with dynamic indices are slow on GPUs): the square's edges where h2 >= 0,
    // then the line from where the square's boundary leaves R to where it enters it again, each
    // between the rays. The boundary's pieces along the rays contribute nothing: they point at
    // the origin.
    vec2 leave = vec2(0.0f, 0.0f);
    vec2 enter = vec2(0.0f, 0.0f);
    float area2 = 0.0f;
    area2 +=
        coverageSquareEdge(vec2(-1.0f, -1.0f), vec2(1.0f, -1.0f), f0, f1, h0, h1, leave, enter);
    area2 += coverageSquareEdge(vec2(1.0f, -1.0f), vec2(1.0f, 1.0f), f1, f2, h0, h1, leave, enter);
    area2 += coverageSquareEdge(vec2(1.0f, 1.0f), vec2(-1.0f, 1.0f), f2, f3, h0, h1, leave, enter);
    area2 +=
        coverageSquareEdge(vec2(-1.0f, 1.0f), vec2(-1.0f, -1.0f), f3, f0, h0, h1, leave, enter);
    area2 += coverageSegment(leave, enter, 0.0f, 1.0f, h0, h1);
    const float fraction = 0.125f * abs(area2); // half the doubled area, over the light's 4
    return (hp > 0.0f ? sg : -sg) * fraction;
}

} // namespace geometry
