// Light-sample masks of one directed silhouette edge (wedges-bitmask). The region R of
// edgeCoverage (lib/Coverage.glsl) — the light points beyond the edge projected from p, seen
// from the light centre, between the rays to its ends — kept as the set of the light's N
// samples it holds rather than as an area: bit i set when sample i lies in R, i.e. when the
// segment from the centre to the sample crosses the projected edge. Over a silhouette group, the
// centre's count plus each sample's signed crossings is the sample's count (hidden where
// non-zero: combine=counts); their parity alone (combine=parity) is exact while the group's
// projection covers no sample twice.
// The CPU model is geometry/LightMask.h (double, exact polygons); the arithmetic up to the
// half-planes is edgeCoverage's, except that an end point of the edge kept whole is projected
// from its own vector (not from an interpolation at l = 1), so that the two edges meeting at a
// vertex agree bit for bit on the ray through it.
// Needs lib/Coverage.glsl. BITMASK_SAMPLES: 32, 64, 128 or 256 (a multiple of 32).
#ifndef BITMASK_SAMPLES
#define BITMASK_SAMPLES 64
#endif
#define BITMASK_WORDS (BITMASK_SAMPLES / 32)

// The edge point at parameter l projected from p onto the light's plane, homogeneous (s, t, w):
// coverageProject, with the ends exact.
vec3 maskProject(float l, vec3 k0, vec3 k1, vec3 d0, vec3 d1, float z0, float z1, float w0,
                 float w1, vec3 pc, CoverageLight light) {
    if (l == 0.0) return coverageProject(0.0, k0, k0, d0, d0, z0, z0, w0, w0, pc, light);
    if (l == 1.0) return coverageProject(0.0, k1, k1, d1, d1, z1, z1, w1, w1, pc, light);
    return coverageProject(l, k0, k1, d0, d1, z0, z1, w0, w1, pc, light);
}

// R as three half-planes dot(h, (s, t, 1)) >= 0 in light coordinates (h0: the side of the ray
// to the first end, h1: of the ray to the second, h2: beyond the projected edge) and the
// orientation sg of the projected edge about the centre; false when R misses the light (no
// sample can be in it).
bool edgeRegion(vec3 p, vec3 e0, vec3 e1, CoverageLight light, out vec3 h0, out vec3 h1,
                out vec3 h2, out float sg) {
    h0 = vec3(0.0);
    h1 = vec3(0.0);
    h2 = vec3(0.0);
    sg = 0.0;
    vec3 pc = p - light.c;
    vec3 k0 = e0 - light.c;
    vec3 k1 = e1 - light.c;
    vec3 d0 = e0 - p;
    vec3 d1 = e1 - p;
    float hp = dot(light.n, pc);
    if (!(abs(hp) > 0.0)) return false;
    float z0 = dot(light.n, k0) / hp;
    float z1 = dot(light.n, k1) / hp;
    float w0 = -dot(light.n, d0) / hp;
    float w1 = -dot(light.n, d1) / hp;
    float lo = 0.0;
    float hi = 1.0;
    if (!coverageClipLe0(-z0, -z1, lo, hi)) return false;
    if (!coverageClipLe0(-w0, -w1, lo, hi)) return false;
    vec3 q0 = maskProject(lo, k0, k1, d0, d1, z0, z1, w0, w1, pc, light);
    vec3 q1 = maskProject(hi, k0, k1, d0, d1, z0, z1, w0, w1, pc, light);
    float cr = q0.x * q1.y - q0.y * q1.x;
    if (cr == 0.0) return false; // through the centre: R is empty
    sg = cr > 0.0 ? 1.0 : -1.0;
    h0 = vec3(-sg * q0.y, sg * q0.x, 0.0);
    h1 = vec3(sg * q1.y, -sg * q1.x, 0.0);
    h2 = -sg * cross(q0, q1);
    float f0 = dot(h2, vec3(-1.0, -1.0, 1.0));
    float f1 = dot(h2, vec3(1.0, -1.0, 1.0));
    float f2 = dot(h2, vec3(1.0, 1.0, 1.0));
    float f3 = dot(h2, vec3(-1.0, 1.0, 1.0));
    return !(f0 < 0.0 && f1 < 0.0 && f2 < 0.0 && f3 < 0.0);
}

// Whether light point y (light coordinates) is in R. A point on a ray belongs to the edge on the
// ray's counter-clockwise side (as if moved a little counter-clockwise about the centre), so
// that of two edges meeting at a vertex exactly one holds it; the edge's own line is closed.
bool regionHolds(vec3 h0, vec3 h1, vec3 h2, float sg, vec2 y) {
    vec3 y1 = vec3(y, 1.0);
    float a = dot(h0, y1);
    float b = dot(h1, y1);
    bool in0 = sg > 0.0 ? a >= 0.0 : a > 0.0;
    bool in1 = sg > 0.0 ? b > 0.0 : b >= 0.0;
    return in0 && in1 && dot(h2, y1) >= 0.0;
}

// The per-pixel shift of the pattern (BITMASK_ROTATED): a Cranley-Patterson rotation by a hash
// of the pixel, the same for every group and edge of the pixel; geometry::maskPixelShift.
uint maskHash(uint x) {
    x = (x ^ (x >> 15)) * 0x2c1b3c6du;
    x = (x ^ (x >> 12)) * 0x297a2d39u;
    return x ^ (x >> 15);
}
vec2 maskPixelShift(ivec2 px) {
    uint h = maskHash(uint(px.x) * 0x9e3779b9u + maskHash(uint(px.y)));
    uint g = maskHash(h);
    return vec2(float(h >> 8), float(g >> 8)) * (1.0 / 8388608.0); // [0, 2)
}
// A sample shifted by `shift` and wrapped back into [-1, 1).
vec2 maskShifted(vec2 y, vec2 shift) {
    vec2 s = y + shift;
    return vec2(s.x >= 1.0 ? s.x - 2.0 : s.x, s.y >= 1.0 ? s.y - 2.0 : s.y);
}
