// Float edge coverage (geometry/Coverage.h). Twin of shaders/lib/Coverage.glsl: every statement
// below has its counterpart there, in the same order and with the same names; only the C++
// spelling differs (0.0f, references for inout).
#include <geometry/Coverage.h>

#include <cmath>

namespace geometry {
namespace {

using glm::vec2;
using glm::vec3;
using std::abs;
using std::max;
using std::min;

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

} // namespace

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
    // Half-planes dot(h, (x, y, 1)) >= 0 bounding the region beyond the projected edge.
    vec3 halves[3];
    halves[0] = vec3(-sg * q0.y, sg * q0.x, 0.0f); // left of the ray to q0
    halves[1] = vec3(sg * q1.y, -sg * q1.x, 0.0f); // right of the ray to q1
    halves[2] = -sg * line;                        // beyond q0 q1 from the centre
    // Clip the light square [-1, 1]^2 by them (Sutherland-Hodgman; at most 4 + 3 vertices).
    vec2 poly[8];
    poly[0] = vec2(-1.0f, -1.0f);
    poly[1] = vec2(1.0f, -1.0f);
    poly[2] = vec2(1.0f, 1.0f);
    poly[3] = vec2(-1.0f, 1.0f);
    int count = 4;
    for (int h = 0; h < 3; ++h) {
        vec2 next[8];
        int nextCount = 0;
        for (int i = 0; i < count; ++i) {
            const vec2 a = poly[i];
            const vec2 b = poly[(i + 1) % count];
            const float fa = dot(halves[h], vec3(a, 1.0f));
            const float fb = dot(halves[h], vec3(b, 1.0f));
            if (fa >= 0.0f) next[nextCount++] = a;
            if ((fa >= 0.0f) != (fb >= 0.0f)) next[nextCount++] = a + (fa / (fa - fb)) * (b - a);
        }
        for (int i = 0; i < nextCount; ++i)
            poly[i] = next[i];
        count = nextCount;
        if (count < 3) return 0.0f;
    }
    float area2 = 0.0f;
    for (int i = 0; i < count; ++i)
        area2 += coverageCross2(poly[i], poly[(i + 1) % count]);
    const float fraction = 0.125f * abs(area2); // half the doubled area, over the light's 4
    return (hp > 0.0f ? sg : -sg) * fraction;
}

} // namespace geometry
