// Signed light coverage of one directed silhouette edge at a point (the per-fragment step of
// penumbra wedges, Assarsson & Akenine-Möller 2003): the float twin of geometry::edgeCoverage
// (geometry/src/Wedge.cpp), same steps in the same order, except that points are taken relative
// to the light centre first (float cancellation in level coordinates).
// - Clip the edge to the part between P and the light's plane, project it from P onto that
//   plane, in the light's (s, t) frame, homogeneous (w = 0: a point at infinity);
// - R = the light points y whose segment from the centre crosses the projected edge: the light
//   square [-1, 1]^2 clipped by three half-planes; its area over the light's (4) is the fraction.
// - Sign: + when the edge occludes towards the centre's side (sum over a loop:
//   V = V_hard - Σ coverage, geometry/Wedge.h).

// The area of R ∩ light is integrated along its boundary (Green: area = ½ Σ cross(start, end)
// over the boundary's oriented segments): the parts of the light square's four edges inside the
// three half-planes, and the part of the line q0 q1 inside the square and the sector. The two
// sector sides pass through the centre (the origin), where cross(start, end) = 0. No polygon is
// built: straight-line code without arrays, which is what makes it cheap per fragment.

// Narrows [lo, hi] to where fa + s (fb - fa) >= 0.
void coverageClip(float fa, float fb, inout float lo, inout float hi) {
    if (fa >= 0.0 && fb >= 0.0) return;
    if (fa < 0.0 && fb < 0.0) {
        hi = lo - 1.0;
        return;
    }
    float s = fa / (fa - fb);
    if (fa < 0.0) lo = max(lo, s);
    else hi = min(hi, s);
}

float coverageHalf(vec3 h, vec2 x) { return dot(h.xy, x) + h.z; }

// cross(start, end) of segment a -> b restricted to the half-planes h0, h1, h2 (and, when
// `inSquare`, to the light square |x|, |y| <= 1).
float coverageSegment(vec2 a, vec2 b, vec3 h0, vec3 h1, vec3 h2, bool inSquare) {
    float lo = 0.0, hi = 1.0;
    coverageClip(coverageHalf(h0, a), coverageHalf(h0, b), lo, hi);
    coverageClip(coverageHalf(h1, a), coverageHalf(h1, b), lo, hi);
    coverageClip(coverageHalf(h2, a), coverageHalf(h2, b), lo, hi);
    if (inSquare) {
        coverageClip(1.0 - a.x, 1.0 - b.x, lo, hi);
        coverageClip(1.0 + a.x, 1.0 + b.x, lo, hi);
        coverageClip(1.0 - a.y, 1.0 - b.y, lo, hi);
        coverageClip(1.0 + a.y, 1.0 + b.y, lo, hi);
    }
    if (!(lo < hi)) return 0.0;
    vec2 p = mix(a, b, lo), q = mix(a, b, hi);
    return p.x * q.y - p.y * q.x;
}

// c: the light's centre; n: its unit normal; uStar, vStar: the dual basis of its half-axes
// (s = dot(uStar, y - c), t = dot(vStar, y - c); FrameUniforms carries all three).
float edgeCoverage(vec3 p, vec3 e0, vec3 e1, vec3 c, vec3 n, vec3 uStar, vec3 vStar) {
    vec3 pc = p - c, x0 = e0 - c, x1 = e1 - c;
    float hp = dot(n, pc);
    if (!(abs(hp) > 0.0)) return 0.0; // on the light's plane (or NaN): nothing between
    float z0 = dot(n, x0) / hp, z1 = dot(n, x1) / hp;
    // The part of the edge between P (z = 1) and the light's plane (z = 0).
    float lo = 0.0, hi = 1.0;
    coverageClip(z0, z1, lo, hi);
    coverageClip(1.0 - z0, 1.0 - z1, lo, hi);
    if (!(lo <= hi)) return 0.0;
    vec3 q[2];
    for (int k = 0; k < 2; ++k) {
        float l = k == 0 ? lo : hi;
        vec3 x = x0 + l * (x1 - x0);
        float z = z0 + l * (z1 - z0);
        float w = max(0.0, 1.0 - z); // rounding must not flip a point at infinity
        vec3 y = x - z * pc;         // (1 - z) (projection - c), relative to the centre
        q[k] = vec3(dot(uStar, y), dot(vStar, y), w);
    }
    float cr = q[0].x * q[1].y - q[0].y * q[1].x;
    if (cr == 0.0) return 0.0; // projected edge through the centre (or empty): measure zero
    float sg = cr > 0.0 ? 1.0 : -1.0;
    vec3 line = cross(q[0], q[1]); // homogeneous line through q0, q1
    vec3 h0 = vec3(-sg * q[0].y, sg * q[0].x, 0.0); // left of the ray to q0
    vec3 h1 = vec3(sg * q[1].y, -sg * q[1].x, 0.0); // right of the ray to q1
    vec3 h2 = -sg * line;                           // beyond q0 q1, away from the centre
    // The light square's edges, counter-clockwise.
    float area2 = coverageSegment(vec2(-1.0, -1.0), vec2(1.0, -1.0), h0, h1, h2, false) +
                  coverageSegment(vec2(1.0, -1.0), vec2(1.0, 1.0), h0, h1, h2, false) +
                  coverageSegment(vec2(1.0, 1.0), vec2(-1.0, 1.0), h0, h1, h2, false) +
                  coverageSegment(vec2(-1.0, 1.0), vec2(-1.0, -1.0), h0, h1, h2, false);
    // The line q0 q1, directed with the region (h2 >= 0) on its left; the square lies within
    // √2 of the centre, so ±1.5 around the line's closest point covers it.
    float nn = dot(h2.xy, h2.xy);
    if (nn > 0.0) {
        vec2 foot = -h2.z * h2.xy / nn;
        vec2 dir = vec2(h2.y, -h2.x) * inversesqrt(nn);
        vec3 none = vec3(0.0, 0.0, 1.0); // always >= 0
        area2 += coverageSegment(foot - 1.5 * dir, foot + 1.5 * dir, h0, h1, none, true);
    }
    float fraction = 0.5 * abs(area2) / 4.0; // the light is [-1, 1]^2 in (s, t)
    return (hp > 0.0 ? sg : -sg) * fraction;
}
