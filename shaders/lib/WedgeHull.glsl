// Conservative hull of a penumbra wedge, built on the GPU from the edge and the light alone.
// The exact wedge is W = E + cone{e_i - c_j} (geometry/Wedge.h; c_j the light's corners). With
// a = the edge's unit direction, every ray r = e_i - c_j splits into a part along a and a part
// p_j in the plane perpendicular to a (the same p_j for both end points). When the edge's line
// misses the light, the p_j lie in a sector of less than 180° between unit directions f and b,
// and p_j = λ_j f + μ_j b with λ_j, μ_j >= 0. Then
//     K = cone(f - s0 a, f + s1 a, b - s0 a, b + s1 a) ⊇ cone{e_i - c_j}
// for s0 = max_j(-α0_j / (λ_j + μ_j)), s1 = max_j(α1_j / (λ_j + μ_j)) (α the parts along a,
// clamped at 0), so H = E + K ⊇ W. H has a fixed shape, 8 triangles: front and back quads
// through the edge (the exact tangent planes of the wedge), one triangle at each end, and a
// quad at infinity. f and b are turned outwards by kHullSlack first (float safety).
// The C++ twin, with the tests of these claims, is geometry/WedgeHull.h.

struct WedgeHull {
    uint kind;        // WEDGE_BOUNDED, WEDGE_FULLSCREEN or WEDGE_DEGENERATE
    vec4 planes[4];   // front, back, side at e0, side at e1: outward unit normal, w = -dot(n, x)
    vec3 rays[4];     // g1 = f - s0 a, g2 = f + s1 a, g3 = b - s0 a, g4 = b + s1 a
};

const float kHullSlack = 1e-3; // radians the sector is widened by on each side; relative s margin

float hullCross(vec2 x, vec2 y) { return x.x * y.y - x.y * y.x; }

vec2 hullRotate(vec2 x, float angle) {
    float cs = cos(angle), sn = sin(angle);
    return vec2(cs * x.x - sn * x.y, sn * x.x + cs * x.y);
}

WedgeHull buildWedgeHull(vec3 e0, vec3 e1, vec3 c, vec3 u, vec3 v) {
    WedgeHull h;
    h.kind = WEDGE_DEGENERATE;
    for (int k = 0; k < 4; ++k) {
        h.planes[k] = vec4(0.0);
        h.rays[k] = vec3(0.0);
    }
    vec3 d = e1 - e0;
    float len = length(d);
    float scale = length(e0 - c) + length(u) + length(v);
    if (!(len > 1e-7 * scale)) return h; // zero-length edge: changes nothing
    vec3 a = d / len;
    vec3 b1 = normalize(abs(a.x) < 0.9 ? cross(a, vec3(1.0, 0.0, 0.0))
                                       : cross(a, vec3(0.0, 1.0, 0.0)));
    vec3 b2 = cross(a, b1);

    vec3 corners[4] = vec3[4](c - u - v, c + u - v, c + u + v, c - u + v);
    vec2 p[4];
    float alpha0[4];
    h.kind = WEDGE_FULLSCREEN;
    for (int j = 0; j < 4; ++j) {
        vec3 r = e0 - corners[j];
        p[j] = vec2(dot(r, b1), dot(r, b2));
        alpha0[j] = dot(r, a);
        if (!(length(p[j]) > 1e-6 * scale)) return h; // the line through a corner
    }
    // The sector: a pair (i, j), j counter-clockwise of i by less than 180°, with every p_k
    // between them. None: the line meets the light (or nearly): no bounded hull.
    int lo = -1, hi = -1;
    for (int i = 0; i < 4 && lo < 0; ++i)
        for (int j = 0; j < 4; ++j) {
            if (i == j || !(hullCross(p[i], p[j]) > 0.0)) continue;
            bool between = true;
            for (int k = 0; k < 4; ++k)
                between = between && hullCross(p[i], p[k]) >= 0.0 &&
                          hullCross(p[k], p[j]) >= 0.0;
            if (between) {
                lo = i;
                hi = j;
                break;
            }
        }
    if (lo < 0) return h;
    vec2 bDir = hullRotate(normalize(p[lo]), -kHullSlack); // clockwise extreme
    vec2 fDir = hullRotate(normalize(p[hi]), kHullSlack);  // counter-clockwise extreme
    float det = hullCross(fDir, bDir);
    // The sector must still be under 180° after widening, with room for float error.
    if (!(det < -1e-6)) return h;
    float s0 = 0.0, s1 = 0.0;
    for (int j = 0; j < 4; ++j) {
        float lambda = hullCross(p[j], bDir) / det;
        float mu = hullCross(fDir, p[j]) / det;
        float sum = lambda + mu;
        if (!(sum > 0.0)) return h;
        s0 = max(s0, -alpha0[j] / sum);
        s1 = max(s1, (alpha0[j] + len) / sum);
    }
    s0 = s0 * (1.0 + kHullSlack) + kHullSlack;
    s1 = s1 * (1.0 + kHullSlack) + kHullSlack;
    vec3 f = fDir.x * b1 + fDir.y * b2;
    vec3 b = bDir.x * b1 + bDir.y * b2;
    // f counter-clockwise of b around a: cross(f, b) = -a ... the winding below assumes
    // cross(f, b) along +a; swap the roles when it is not.
    if (dot(cross(f, b), a) < 0.0) {
        vec3 t = f;
        f = b;
        b = t;
    }
    h.rays[0] = f - s0 * a;
    h.rays[1] = f + s1 * a;
    h.rays[2] = b - s0 * a;
    h.rays[3] = b + s1 * a;
    vec3 nFront = normalize(cross(a, f)) * (dot(cross(a, f), b) > 0.0 ? -1.0 : 1.0);
    vec3 nBack = normalize(cross(a, b)) * (dot(cross(a, b), f) > 0.0 ? -1.0 : 1.0);
    vec3 nSide0 = normalize(cross(h.rays[0], h.rays[2]));
    if (dot(nSide0, a) > 0.0) nSide0 = -nSide0;
    vec3 nSide1 = normalize(cross(h.rays[1], h.rays[3]));
    if (dot(nSide1, a) < 0.0) nSide1 = -nSide1;
    h.planes[0] = vec4(nFront, -dot(nFront, e0));
    h.planes[1] = vec4(nBack, -dot(nBack, e0));
    h.planes[2] = vec4(nSide0, -dot(nSide0, e0));
    h.planes[3] = vec4(nSide1, -dot(nSide1, e1));
    h.kind = WEDGE_BOUNDED;
    return h;
}

// The hull's 24 vertices (8 triangles, outward counter-clockwise) as corner ids:
// 0 = e0, 1 = e1, 2..5 = rays g1..g4 at infinity. Front (e0, g1, g2, e1), back (e0, e1, g4, g3),
// side at e0 (e0, g3, g1), side at e1 (e1, g2, g4), at infinity (g1, g3, g4, g2).
int wedgeHullCorner(int k) {
    const int corners[24] = int[24](0, 2, 3, 0, 3, 1, 0, 1, 5, 0, 5, 4, 0, 4, 2, 1, 3, 5, 2,
                                    4, 5, 2, 5, 3);
    return corners[k];
}
