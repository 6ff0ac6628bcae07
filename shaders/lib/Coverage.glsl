// Per-fragment coverage of one directed silhouette edge (DESIGN.md §4; Assarsson &
// Akenine-Möller 2003, §3-4): the signed fraction of the light between the edge projected from p
// and the light centre, zero outside the edge's exact wedge; V(p) = V_hard(p) - the sum over a
// silhouette loop. Pure functions, no bindings. The arithmetic of the double
// geometry::edgeCoverage (geometry/src/Wedge.cpp explains it), arranged for float (and with the
// area integrated along the boundary rather than a polygon clipped: no arrays); the float C++
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

// Restricts [lo, hi] to the l where a + l (b - a) lies in the half-plane dot(h, (x, y, 1)) >= 0
// (closed, like the polygon clipping of the double version); false when that leaves nothing.
bool coverageClipHalf(vec3 h, vec2 a, vec2 b, inout float lo, inout float hi) {
    return coverageClipLe0(-dot(h, vec3(a, 1.0)), -dot(h, vec3(b, 1.0)), lo, hi);
}

// Twice the area of R (edgeCoverage) is the sum of cross(start, end) over the pieces of its
// boundary (Green, the centre as origin). One piece: a + l (b - a), l in [lo, hi], between the
// rays h0, h1.
float coverageSegment(vec2 a, vec2 b, float lo, float hi, vec3 h0, vec3 h1) {
    if (!coverageClipHalf(h0, a, b, lo, hi)) return 0.0;
    if (!coverageClipHalf(h1, a, b, lo, hi)) return 0.0;
    return coverageCross2(a + lo * (b - a), a + hi * (b - a));
}

// The piece of R's boundary along the light square's edge a -> b (counter-clockwise), where fa,
// fb are the line's h2 at a and b (R: h2 >= 0). Where the edge crosses the line, the crossing is
// kept as the start (leave) or end (enter) of the boundary's piece along the line: computed once
// for both pieces, so that they meet exactly however obliquely the line crosses the edge.
float coverageSquareEdge(vec2 a, vec2 b, float fa, float fb, vec3 h0, vec3 h1,
                         inout vec2 leave, inout vec2 enter) {
    if (fa < 0.0 && fb < 0.0) return 0.0;
    float lo = 0.0;
    float hi = 1.0;
    if (fa < 0.0 || fb < 0.0) {
        float l = fa / (fa - fb);
        vec2 x = a + l * (b - a);
        if (fa >= 0.0) {
            leave = x;
            hi = l;
        } else {
            enter = x;
            lo = l;
        }
    }
    return coverageSegment(a, b, lo, hi, h0, h1);
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
    // R: the light points beyond q0 q1 from the centre, between the rays to q0 and q1; the
    // half-planes dot(h, (x, y, 1)) >= 0 bounding it.
    vec3 h0 = vec3(-sg * q0.y, sg * q0.x, 0.0); // left of the ray to q0
    vec3 h1 = vec3(sg * q1.y, -sg * q1.x, 0.0); // right of the ray to q1
    vec3 h2 = -sg * line;                        // beyond q0 q1 from the centre
    // h2 at the light's corners (s, t) = (-1, -1), (1, -1), (1, 1), (-1, 1), counter-clockwise;
    // all negative: the light is wholly on the centre's side of the line.
    float f0 = dot(h2, vec3(-1.0, -1.0, 1.0));
    float f1 = dot(h2, vec3(1.0, -1.0, 1.0));
    float f2 = dot(h2, vec3(1.0, 1.0, 1.0));
    float f3 = dot(h2, vec3(-1.0, 1.0, 1.0));
    if (f0 < 0.0 && f1 < 0.0 && f2 < 0.0 && f3 < 0.0) return 0.0;
    // The area of R integrated along its boundary, counter-clockwise, without building the
    // polygon (arrays with dynamic indices are slow on GPUs): the square's edges where h2 >= 0,
    // then the line from where the square's boundary leaves R to where it enters it again, each
    // between the rays. The boundary's pieces along the rays contribute nothing: they point at
    // the origin.
    vec2 leave = vec2(0.0, 0.0);
    vec2 enter = vec2(0.0, 0.0);
    float area2 = 0.0;
    area2 += coverageSquareEdge(vec2(-1.0, -1.0), vec2(1.0, -1.0), f0, f1, h0, h1, leave, enter);
    area2 += coverageSquareEdge(vec2(1.0, -1.0), vec2(1.0, 1.0), f1, f2, h0, h1, leave, enter);
    area2 += coverageSquareEdge(vec2(1.0, 1.0), vec2(-1.0, 1.0), f2, f3, h0, h1, leave, enter);
    area2 += coverageSquareEdge(vec2(-1.0, 1.0), vec2(-1.0, -1.0), f3, f0, h0, h1, leave, enter);
    area2 += coverageSegment(leave, enter, 0.0, 1.0, h0, h1);
    float fraction = 0.125 * abs(area2); // half the doubled area, over the light's 4
    return (hp > 0.0 ? sg : -sg) * fraction;
}
