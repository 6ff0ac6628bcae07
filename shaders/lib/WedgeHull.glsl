// Conservative hull of a penumbra wedge with a fixed topology (8 triangles, 24 vertices), built
// per vertex for vertex pulling. Pure functions, no bindings. The construction, its float-safety
// margins and the vertex order are explained in geometry/include/geometry/WedgeHull.h; the float
// C++ twin is geometry/src/WedgeHull.cpp: same names, same statements in the same order (the
// tests in tests/geometry/WedgeHullTest.cpp run that twin). Change both together.
//
// Vertex shader use (one instance or 24 vertices per directed silhouette edge):
//     WedgeHull hull = wedgeHull(e0, e1, frame.lightCenter.xyz, frame.lightU.xyz, frame.lightV.xyz);
//     gl_Position = wedgeHullClipVertex(hull, gl_VertexID % kWedgeHullVertexCount, frame.viewProj);
//     vPlanes = hull.planes;  // flat, for wedgeHullContains in the fragment shader
// Draw back faces only, no depth test, depth clamp on (the face the view ray leaves through may
// lie in front of the near plane when the camera is inside the hull).

const int kWedgeHullBounded = 0;    // the 24 vertices bound the exact wedge
const int kWedgeHullFullscreen = 1; // no useful bound: vertices 0..2 cover the viewport
const int kWedgeHullDegenerate = 2; // zero-length (or non-finite) edge: draw nothing
const int kWedgeHullVertexCount = 24;

// Vertex slots: 0 e0, 1 e1, 2..5 g1..g4 (w = 0). Outward winding:
//   front  (e1, e0, g1) (e1, g1, g2)    back   (e0, e1, g4) (e0, g4, g3)
//   side 0 (e0, g3, g1)                 side 1 (e1, g2, g4)
//   far    (g1, g3, g4) (g1, g4, g2)
const int kWedgeHullIndex[kWedgeHullVertexCount] = int[kWedgeHullVertexCount](
    1, 0, 2, 1, 2, 3, // front
    0, 1, 5, 0, 5, 4, // back
    0, 4, 2,          // side at e0
    1, 3, 5,          // side at e1
    2, 4, 5, 2, 5, 3  // far
);

struct WedgeHull {
    int kind;
    vec3 e0;
    vec3 e1;
    vec3 g[4];      // g1..g4: unit directions of the cone's edges (Bounded only)
    vec4 planes[4]; // front, back, side at e0, side at e1: xyz unit outward normal,
                    // w = -dot(n, point); inside when dot(n, p) + w <= 0
};

// See WedgeHull.cpp for the reasoning behind each constant.
const float kWedgeHullRound = 1.0e-6;
const float kWedgeHullRoundLen = 5.0e-7;
const float kWedgeHullAngleBase = 1.0e-6;
const float kWedgeHullAngleMax = 1.0e-2;
const float kWedgeHullMinHalfCos = 0.017452406;

float wedgeHullCross2(vec2 a, vec2 b) {
    return a.x * b.y - a.y * b.x;
}

// Solid angle (up to a constant) of the directions over the sector from fw to bw that lie below
// the plane A = dot(P, h).
float wedgeHullSpread(vec2 h, vec2 fw, vec2 bw) {
    float r = 1.0 / sqrt(1.0 + dot(h, h));
    float sb = clamp(wedgeHullCross2(h, bw) * r, -1.0, 1.0);
    float sf = clamp(wedgeHullCross2(h, fw) * r, -1.0, 1.0);
    return asin(sb) - asin(sf);
}

// A side plane A = dot(P, h) with dot(P[k], h) <= B[k]: the best of W's own side facets, then
// moved along -m by the rounding margins.
vec2 wedgeHullSide(vec2 P[4], float B[4], vec2 fw, vec2 bw, vec2 m, float rho) {
    vec2 h = vec2(0.0);
    float best = -3.0e38;
    bool found = false;
    for (int i = 0; i < 3; ++i) {
        for (int j = i + 1; j < 4; ++j) {
            float det = wedgeHullCross2(P[i], P[j]);
            if (!(abs(det) > 1.0e-4 * length(P[i]) * length(P[j]))) continue;
            vec2 c = vec2(B[i] * P[j].y - B[j] * P[i].y, P[i].x * B[j] - P[j].x * B[i]) / det;
            bool feasible = true;
            for (int k = 0; k < 4; ++k) {
                float slack = 1.0e-5 * (abs(B[k]) + length(P[k]) * length(c));
                feasible = feasible && dot(P[k], c) <= B[k] + slack;
            }
            float spread = wedgeHullSpread(c, fw, bw);
            if (feasible && spread > best) {
                best = spread;
                h = c;
                found = true;
            }
        }
    }
    if (!found) { // (parallel rays only) the plane through the lowest ray along m
        float lo = 3.0e38;
        for (int k = 0; k < 4; ++k)
            lo = min(lo, B[k] / dot(P[k], m));
        h = lo * m;
    }
    for (int pass = 0; pass < 2; ++pass) {
        float nh = 1.0 + length(h);
        float tau = 0.0;
        for (int k = 0; k < 4; ++k) {
            float margin =
                nh * (2.0 * rho + kWedgeHullAngleBase * (abs(B[k]) + length(P[k])));
            tau = max(tau, (dot(P[k], h) - B[k] + margin) / dot(P[k], m));
        }
        h = h - tau * m;
    }
    return h;
}

// The hull of the wedge of edge e0 -> e1 for the light c + s u + t v (s, t in [-1, 1]).
WedgeHull wedgeHull(vec3 e0, vec3 e1, vec3 c, vec3 u, vec3 v) {
    WedgeHull hull;
    hull.kind = kWedgeHullDegenerate;
    hull.e0 = e0;
    hull.e1 = e1;
    for (int i = 0; i < 4; ++i) {
        hull.g[i] = vec3(0.0);
        hull.planes[i] = vec4(0.0);
    }
    vec3 d = e1 - e0;
    float len = length(d);
    if (!(len > 0.0) || isinf(len)) return hull; // zero length, or not finite
    hull.kind = kWedgeHullFullscreen;

    // Orthonormal frame (x, y, a), cross(x, y) = a; 2D vectors below are in (x, y).
    vec3 a = d / len;
    vec3 x =
        normalize(cross(abs(a.x) < 0.5 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0), a));
    vec3 y = cross(a, x);

    // Rays from e0 through the corners c_j = c + s u + t v, (s, t) = (-1, -1) (1, -1) (1, 1)
    // (-1, 1): e0 - c_j = P[j] + A[j] a; e1's rays are P[j] + (A[j] + len) a.
    vec3 k = e0 - c;
    vec2 o = vec2(dot(k, x), dot(k, y));
    vec2 pu = vec2(dot(u, x), dot(u, y));
    vec2 pv = vec2(dot(v, x), dot(v, y));
    float ak = dot(k, a);
    float au = dot(u, a);
    float av = dot(v, a);
    // Bound on the error of every P[j] and A[j] against the exact rays in this float frame.
    float rho =
        kWedgeHullRound * (length(k) + length(u) + length(v)) + kWedgeHullRoundLen * len;
    vec2 P[4];
    float A[4];
    float minPerp = 3.0e38;
    for (int j = 0; j < 4; ++j) {
        float s = (j == 1 || j == 2) ? 1.0 : -1.0;
        float t = (j >= 2) ? 1.0 : -1.0;
        P[j] = o - s * pu - t * pv;
        A[j] = ak - s * au - t * av;
        minPerp = min(minPerp, length(P[j]));
    }
    // The rays' directions in the plane ⟂ a are known to rho / |P[j]|; where that exceeds
    // kWedgeHullAngleMax the sector cannot be trusted. (Compared before dividing: minPerp may
    // be 0.)
    if (!(3.0 * rho < (kWedgeHullAngleMax - kWedgeHullAngleBase) * minPerp)) return hull;

    // The sector's clockwise-most (f) and counter-clockwise-most (b) ray; meaningful only when
    // the P[j] lie in an open half-plane, which the test after widening checks.
    int f = 0;
    int b = 0;
    for (int j = 1; j < 4; ++j) {
        if (wedgeHullCross2(P[f], P[j]) < 0.0) f = j;
        if (wedgeHullCross2(P[b], P[j]) > 0.0) b = j;
    }
    vec2 fu = P[f] / length(P[f]);
    vec2 bu = P[b] / length(P[b]);
    // Widening, per side: every ray within 3 rho of a boundary is turned 3 rho inside it.
    float thetaF = kWedgeHullAngleBase;
    float thetaB = kWedgeHullAngleBase;
    for (int j = 0; j < 4; ++j) {
        float need = kWedgeHullAngleBase + 3.0 * rho / length(P[j]);
        if (wedgeHullCross2(fu, P[j]) < 3.0 * rho) thetaF = max(thetaF, need);
        if (wedgeHullCross2(P[j], bu) < 3.0 * rho) thetaB = max(thetaB, need);
    }
    // cos and sin to ~theta^3 / 6 <= 2e-7 of theta: GPU sin and cos may have absolute errors of
    // ~5e-7, more than the smallest theta.
    float csF = 1.0 - 0.5 * thetaF * thetaF;
    float snF = thetaF;
    float csB = 1.0 - 0.5 * thetaB * thetaB;
    float snB = thetaB;
    vec2 fw = vec2(csF * fu.x + snF * fu.y, csF * fu.y - snF * fu.x); // fu turned by -thetaF
    vec2 bw = vec2(csB * bu.x - snB * bu.y, csB * bu.y + snB * bu.x); // bu turned by +thetaB
    vec2 sum = fw + bw;
    float cHalf = 0.5 * length(sum); // cos(half the widened sector)
    if (!(wedgeHullCross2(fw, bw) > 0.0 && cHalf >= kWedgeHullMinHalfCos)) return hull;
    vec2 m = sum / length(sum); // the bisector
    // Every ray at least 1.5 rho inside both boundaries, so the exact rays (within rho) are
    // strictly inside.
    for (int j = 0; j < 4; ++j) {
        if (!(wedgeHullCross2(fw, P[j]) >= 1.5 * rho && wedgeHullCross2(P[j], bw) >= 1.5 * rho))
            return hull;
    }

    // Side planes: at e0 the plane A = dot(P, h0) with every ray above it, at e1 A = dot(P, h1)
    // with every ray below it (e1's rays are the higher ones, A + len).
    float lower[4];
    float upper[4];
    for (int j = 0; j < 4; ++j) {
        lower[j] = A[j];
        upper[j] = -(A[j] + len);
    }
    vec2 h0 = wedgeHullSide(P, lower, fw, bw, m, rho);
    vec2 h1 = -wedgeHullSide(P, upper, fw, bw, m, rho);
    // The cone's edges: where the side planes meet the front and back planes.
    float f0 = dot(fw, h0);
    float f1 = dot(fw, h1);
    float b0 = dot(bw, h0);
    float b1 = dot(bw, h1);
    if (!(f1 > f0 && b1 > b0)) return hull; // (the sides would cross inside the sector)

    vec3 F = fw.x * x + fw.y * y;
    vec3 B = bw.x * x + bw.y * y;
    hull.g[0] = normalize(F + f0 * a);
    hull.g[1] = normalize(F + f1 * a);
    hull.g[2] = normalize(B + b0 * a);
    hull.g[3] = normalize(B + b1 * a);

    // Planes, pushed outward by the rounding of their offsets and of the normals against E.
    float push = kWedgeHullRound * (length(e0) + length(e1));
    vec3 nFront = fw.y * x - fw.x * y;
    vec3 nBack = bw.x * y - bw.y * x;
    vec3 nSide0 = normalize(h0.x * x + h0.y * y - a);
    vec3 nSide1 = normalize(a - h1.x * x - h1.y * y);
    hull.planes[0] = vec4(nFront, -dot(nFront, e0) - push);
    hull.planes[1] = vec4(nBack, -dot(nBack, e0) - push);
    hull.planes[2] = vec4(nSide0, -dot(nSide0, e0) - push);
    hull.planes[3] = vec4(nSide1, -dot(nSide1, e1) - push);
    hull.kind = kWedgeHullBounded;
    return hull;
}

// Vertex `index` (0..23): a point (w = 1) or a direction (w = 0); vec4(0) unless Bounded.
vec4 wedgeHullVertex(WedgeHull hull, int index) {
    if (hull.kind != kWedgeHullBounded) return vec4(0.0);
    int slot = kWedgeHullIndex[index];
    if (slot == 0) return vec4(hull.e0, 1.0);
    if (slot == 1) return vec4(hull.e1, 1.0);
    return vec4(hull.g[slot - 2], 0.0);
}

// Clip-space position: the hull through viewProj when Bounded; when Fullscreen, vertices 0..2 a
// triangle covering the viewport, clockwise in NDC (back-facing under glFrontFace(GL_CCW)) and
// the rest vec4(0); when Degenerate, vec4(0).
vec4 wedgeHullClipVertex(WedgeHull hull, int index, mat4 viewProj) {
    if (hull.kind == kWedgeHullFullscreen) {
        if (index == 0) return vec4(-1.0, -1.0, 0.0, 1.0);
        if (index == 1) return vec4(-1.0, 3.0, 0.0, 1.0);
        if (index == 2) return vec4(3.0, -1.0, 0.0, 1.0);
        return vec4(0.0);
    }
    return viewProj * wedgeHullVertex(hull, index);
}

// Early-out plane test: p inside all four planes (always true for zero planes, i.e. Fullscreen).
bool wedgeHullContains(vec4 planes[4], vec3 p) {
    for (int i = 0; i < 4; ++i) {
        if (dot(vec3(planes[i]), p) + planes[i].w > 0.0) return false;
    }
    return true;
}
