// Per-fragment coverage of one directed silhouette edge (DESIGN.md §4; Assarsson &
// Akenine-Möller 2003, §3-4): the signed fraction of the light between the edge projected from p
// and the light centre, zero outside the edge's exact wedge; V(p) = V_hard(p) - the sum over a
// silhouette loop. Pure functions, no bindings. The arithmetic of the double
// geometry::edgeCoverage (geometry/src/Wedge.cpp explains it), arranged for float; the float C++
// twin is geometry/src/Coverage.cpp: same names, same statements in the same order (tests in
// tests/geometry/WedgeHullTest.cpp compare it with the double version). Change both together.

// The light c + s u + t v (s, t in [-1, 1]) with its unit normal n (along cross(u, v)) and the
// dual basis: s = dot(uStar, y - c), t = dot(vStar, y - c) for y in the light's plane.
struct CoverageLight {
    vec3 c;
    vec3 u;
    vec3 v;
    vec3 n;
    vec3 uStar;
    vec3 vStar;
};

float coverageCross2(vec2 a, vec2 b) {
    return a.x * b.y - a.y * b.x;
}

// Restricts [lo, hi] to the l where f0 + l (f1 - f0) <= 0; false when that leaves nothing.
bool coverageClipLe0(float f0, float f1, inout float lo, inout float hi) {
    if (f0 <= 0.0 && f1 <= 0.0) return lo <= hi;
    if (f0 > 0.0 && f1 > 0.0) return false;
    float l = f0 / (f0 - f1);
    if (f0 > 0.0)
        lo = max(lo, l);
    else
        hi = min(hi, l);
    return lo <= hi;
}

// The edge point at parameter l projected from p onto the light's plane, homogeneous (s, t, w)
// (w = 0: at infinity); y = (x - c) - z (p - c) near the light's plane, (x - p) + w (p - c) near
// p's level, so that neither form cancels.
vec3 coverageProject(float l, vec3 k0, vec3 k1, vec3 d0, vec3 d1, float z0, float z1, float w0,
                     float w1, vec3 pc, CoverageLight light) {
    float z = z0 + l * (z1 - z0);
    float w = max(0.0, w0 + l * (w1 - w0)); // rounding must not flip a point at infinity
    vec3 y = z < 0.5 ? (k0 + l * (k1 - k0)) - z * pc : (d0 + l * (d1 - d0)) + w * pc;
    return vec3(dot(light.uStar, y), dot(light.vStar, y), w);
}

CoverageLight coverageLight(vec3 c, vec3 u, vec3 v) {
    CoverageLight light;
    light.c = c;
    light.u = u;
    light.v = v;
    light.n = normalize(cross(u, v));
    vec3 a = cross(v, light.n);
    vec3 b = cross(light.n, u);
    light.uStar = a / dot(u, a);
    light.vStar = b / dot(v, b);
    return light;
}

float edgeCoverage(vec3 p, vec3 e0, vec3 e1, CoverageLight light) {
    vec3 pc = p - light.c;
    vec3 k0 = e0 - light.c;
    vec3 k1 = e1 - light.c;
    vec3 d0 = e0 - p;
    vec3 d1 = e1 - p;
    float hp = dot(light.n, pc);
    if (!(abs(hp) > 0.0)) return 0.0; // on the light's plane: nothing in between
    // Heights over p's height (z) and depths below p's level (w = 1 - z), each from its own
    // accurate difference.
    float z0 = dot(light.n, k0) / hp;
    float z1 = dot(light.n, k1) / hp;
    float w0 = -dot(light.n, d0) / hp;
    float w1 = -dot(light.n, d1) / hp;
    // Only the part of the edge strictly between p's level and the light's plane can block.
    float lo = 0.0;
    float hi = 1.0;
    if (!coverageClipLe0(-z0, -z1, lo, hi)) return 0.0;
    if (!coverageClipLe0(-w0, -w1, lo, hi)) return 0.0;
    vec3 q0 = coverageProject(lo, k0, k1, d0, d1, z0, z1, w0, w1, pc, light);
    vec3 q1 = coverageProject(hi, k0, k1, d0, d1, z0, z1, w0, w1, pc, light);
    float cr = q0.x * q1.y - q0.y * q1.x;
    if (cr == 0.0) return 0.0; // projected edge through the centre (or empty)
    float sg = cr > 0.0 ? 1.0 : -1.0;
    vec3 line = cross(q0, q1); // homogeneous line through q0, q1
    // Half-planes dot(h, (x, y, 1)) >= 0 bounding the region beyond the projected edge.
    vec3 halves[3];
    halves[0] = vec3(-sg * q0.y, sg * q0.x, 0.0); // left of the ray to q0
    halves[1] = vec3(sg * q1.y, -sg * q1.x, 0.0); // right of the ray to q1
    halves[2] = -sg * line;                       // beyond q0 q1 from the centre
    // Clip the light square [-1, 1]^2 by them (Sutherland-Hodgman; at most 4 + 3 vertices).
    vec2 poly[8];
    poly[0] = vec2(-1.0, -1.0);
    poly[1] = vec2(1.0, -1.0);
    poly[2] = vec2(1.0, 1.0);
    poly[3] = vec2(-1.0, 1.0);
    int count = 4;
    for (int h = 0; h < 3; ++h) {
        vec2 next[8];
        int nextCount = 0;
        for (int i = 0; i < count; ++i) {
            vec2 a = poly[i];
            vec2 b = poly[(i + 1) % count];
            float fa = dot(halves[h], vec3(a, 1.0));
            float fb = dot(halves[h], vec3(b, 1.0));
            if (fa >= 0.0) next[nextCount++] = a;
            if ((fa >= 0.0) != (fb >= 0.0)) next[nextCount++] = a + (fa / (fa - fb)) * (b - a);
        }
        for (int i = 0; i < nextCount; ++i)
            poly[i] = next[i];
        count = nextCount;
        if (count < 3) return 0.0;
    }
    float area2 = 0.0;
    for (int i = 0; i < count; ++i)
        area2 += coverageCross2(poly[i], poly[(i + 1) % count]);
    float fraction = 0.125 * abs(area2); // half the doubled area, over the light's 4
    return (hp > 0.0 ? sg : -sg) * fraction;
}
