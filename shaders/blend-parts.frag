// wedges-blend, per batch and set of parts: resolve each part's state of the batch's silhouette
// at P and blend it into the final state (Forest, Barthe & Paulin 2006, slides "Penumbra blending
// [4/6]-[6/6]"; the arithmetic of geometry/models/BlendModel.h resolvePart, blendPart and its packing).
// Drawn twice per batch and set, with the stencil selecting where the group's light centre is
// occluded (uCentre = 1) or not (0). The final state is read from the textures this pass writes:
// each pixel is written once per draw, after a texture barrier.
// Variants (#defines prepended by the loader; the defaults are the paper's):
//   BLEND_PARTS 1 | 4 | 8   R: the part is [0, 1]^2 (R = 1: the centre at (1/2, 1/2); R = 4: at
//                           the corner (0, 0)) or the triangle 0 <= y <= x <= 1 (R = 8)
//   BLEND_BITS 8 | 16       packing of the stored states (packPart8 / packPart16)
//   BLEND_CENTROID 0 | 1    overlap estimate Overlap::Paper or Overlap::Centroid
// Inputs: the layout of shaders/wedge-parts.frag; the set's final state at TEXUNIT_FINAL0 + i:
//   8 bits: 0 rect (packRect8), 1 coef (vCoef | centroid x << 8 | centroid y << 16);
//   16 bits: 0 min x | min y << 16, 1 max x | max y << 16, 2 vCoef | centroid x << 16,
//   3 centroid y; one component per part of the set (R = 1: x only). Paper keeps no centroid.
#ifndef BLEND_PARTS
#define BLEND_PARTS 4
#endif
#ifndef BLEND_BITS
#define BLEND_BITS 8
#endif
#ifndef BLEND_CENTROID
#define BLEND_CENTROID 0
#endif

#include "lib/Bindings.h"

#if BLEND_PARTS == 1
#define SET_PARTS 1
#else
#define SET_PARTS 4
#endif
#if BLEND_BITS == 16
#define FINAL_TARGETS 4
#else
#define FINAL_TARGETS 2
#endif

#if BLEND_PARTS == 1
layout(binding = TEXUNIT_PARTS0 + 0) uniform sampler2D tState; // coverage, windings, moments
#else
layout(binding = TEXUNIT_PARTS0 + 0) uniform sampler2D tCoverage;
layout(binding = TEXUNIT_PARTS0 + 1) uniform sampler2D tWindings;
layout(binding = TEXUNIT_PARTS0 + 2) uniform sampler2D tMomentX;
layout(binding = TEXUNIT_PARTS0 + 3) uniform sampler2D tMomentY;
layout(binding = TEXUNIT_PARTS0 + 5) uniform sampler2D tBounds1;
layout(binding = TEXUNIT_PARTS0 + 6) uniform sampler2D tBounds2;
layout(binding = TEXUNIT_PARTS0 + 7) uniform sampler2D tBounds3;
#endif
layout(binding = TEXUNIT_PARTS0 + 4) uniform sampler2D tBounds0;
layout(binding = TEXUNIT_FINAL0 + 0) uniform usampler2D tFinal0;
layout(binding = TEXUNIT_FINAL0 + 1) uniform usampler2D tFinal1;
#if FINAL_TARGETS == 4
layout(binding = TEXUNIT_FINAL0 + 2) uniform usampler2D tFinal2;
layout(binding = TEXUNIT_FINAL0 + 3) uniform usampler2D tFinal3;
#endif

layout(location = 0) uniform float uCentre; // 1: the group occludes the light centre here

layout(location = 0) out uvec4 oFinal0;
layout(location = 1) out uvec4 oFinal1;
#if FINAL_TARGETS == 4
layout(location = 2) out uvec4 oFinal2;
layout(location = 3) out uvec4 oFinal3;
#endif

// The part in its own coordinates (BlendModel.cpp radialPart).
#if BLEND_PARTS == 8
const float kPartArea = 0.5;
const vec2 kPartCentroid = vec2(2.0 / 3.0, 1.0 / 3.0);
#else
const float kPartArea = 1.0;
const vec2 kPartCentroid = vec2(0.5, 0.5);
#endif

// --- Packing (BlendModel.cpp packUnorm8*, packRect8, packRect16, packCoef8/16) ---
float clamp01(float v) { return v > 0.0 ? min(v, 1.0) : 0.0; }
uint packUnorm8(float v) { return uint(floor(clamp01(v) * 255.0 + 0.5)); }
uint packUnorm8Down(float v) { return uint(floor(clamp01(v) * 255.0)); }
uint packUnorm8Up(float v) { return uint(ceil(clamp01(v) * 255.0)); }
float unpackUnorm8(uint bits) { return float(bits & 255u) / 255.0; }
uint packRect8(vec4 r) {
    return packUnorm8Down(r.x) | (packUnorm8Down(r.y) << 8u) | (packUnorm8Up(r.z) << 16u) |
           (packUnorm8Up(r.w) << 24u);
}
vec4 unpackRect8(uint bits) {
    return vec4(unpackUnorm8(bits), unpackUnorm8(bits >> 8u), unpackUnorm8(bits >> 16u),
                unpackUnorm8(bits >> 24u));
}
uint packUnorm16(float v) { return uint(floor(clamp01(v) * 65535.0 + 0.5)); }
uint packUnorm16Down(float v) { return uint(floor(clamp01(v) * 65535.0)); }
uint packUnorm16Up(float v) { return uint(ceil(clamp01(v) * 65535.0)); }
float unpackUnorm16(uint bits) { return float(bits & 65535u) / 65535.0; }

bool rectEmpty(vec4 r) { return r.x > r.z || r.y > r.w; }
vec4 rectExtend(vec4 r, vec2 p) {
    return rectEmpty(r) ? vec4(p, p) : vec4(min(r.xy, p), max(r.zw, p));
}
vec4 rectUnite(vec4 a, vec4 b) {
    if (rectEmpty(a)) return b;
    if (rectEmpty(b)) return a;
    return vec4(min(a.xy, b.xy), max(a.zw, b.zw));
}
vec2 rectClamp(vec2 p, vec4 r) { return rectEmpty(r) ? p : clamp(p, r.xy, r.zw); }

// |r ∩ part| (part coordinates; r lies in [0, 1]^2).
float rectArea(vec4 r) {
    if (rectEmpty(r)) return 0.0;
#if BLEND_PARTS == 8
    // The triangle 0 <= y <= x: over [max(x0, y0), min(x1, y1)] the column runs from y0 to x,
    // beyond max(x0, y1) it is full.
    float a = max(r.x, r.y), b = min(r.z, r.w);
    float area = b > a ? 0.5 * ((b - r.y) * (b - r.y) - (a - r.y) * (a - r.y)) : 0.0;
    float from = max(r.x, r.w);
    if (r.z > from) area += (r.z - from) * (r.w - r.y);
    return area;
#else
    return (r.z - r.x) * (r.w - r.y);
#endif
}

struct PartState {
    float vCoef; // occluded fraction of the part
    vec4 rect;   // (min x, min y, max x, max y), empty = (1, 1, 0, 0)
    vec2 mean;     // centroid of the occluded region (`centroid` is a GLSL keyword)
};

// The next corner's winding from edgePartSet's mixed-radix number (exact in float: each digit
// in [-8, 7]).
float nextWinding(inout float n) {
    float w = n - 16.0 * floor((n + 8.0) / 16.0);
    n = (n - w) / 16.0;
    return w;
}

// The silhouette's resolved state of one part (resolvePart): vCoef = clamp(C + coverage), the
// rectangle = edge bounds ∪ occluded corners, the centroid of the occluded region.
PartState resolvePart(float coverage, float windings, vec4 edgeBounds, vec2 moment) {
    PartState s;
    s.vCoef = clamp(uCentre + coverage, 0.0, 1.0);
    s.rect = vec4(1.0, 1.0, 0.0, 0.0);
    s.mean = kPartCentroid;
    if (!(s.vCoef > 1e-6)) { // no occlusion: no rectangle
        s.vCoef = 0.0;
        return s;
    }
    s.rect = edgeBounds;
    float n = windings;
#if BLEND_PARTS == 1
    // Corners (0, 0), (1, 0), (1, 1), (0, 1); the centre is none of them.
    if (uCentre + nextWinding(n) >= 0.5) s.rect = rectExtend(s.rect, vec2(0.0, 0.0));
    if (uCentre + nextWinding(n) >= 0.5) s.rect = rectExtend(s.rect, vec2(1.0, 0.0));
    if (uCentre + nextWinding(n) >= 0.5) s.rect = rectExtend(s.rect, vec2(1.0, 1.0));
    if (uCentre + nextWinding(n) >= 0.5) s.rect = rectExtend(s.rect, vec2(0.0, 1.0));
#else
    // The centre's corner (0, 0), then (1, 0), (1, 1) and, for a quadrant, (0, 1).
    if (uCentre > 0.5) s.rect = rectExtend(s.rect, vec2(0.0, 0.0));
    if (uCentre + nextWinding(n) >= 0.5) s.rect = rectExtend(s.rect, vec2(1.0, 0.0));
    if (uCentre + nextWinding(n) >= 0.5) s.rect = rectExtend(s.rect, vec2(1.0, 1.0));
#if BLEND_PARTS == 4
    if (uCentre + nextWinding(n) >= 0.5) s.rect = rectExtend(s.rect, vec2(0.0, 1.0));
#endif
#endif
#if BLEND_CENTROID
    s.mean = rectClamp((uCentre * kPartCentroid + moment) / (uCentre + coverage), s.rect);
#endif
    return s;
}

#if BLEND_CENTROID
// --- Overlap::Centroid: separable linear densities (BlendModel.cpp densityOf, overlapOf) ---
// Polynomials c.x + c.y x + c.z x² + c.w x³.
float polyPrimitive(vec4 c, float x) {
    return x * (c.x + x * (c.y / 2.0 + x * (c.z / 3.0 + x * c.w / 4.0)));
}
float polyIntegral(vec4 c, float a, float b) { return polyPrimitive(c, b) - polyPrimitive(c, a); }
float polyEval(vec4 c, float x) { return c.x + x * (c.y + x * (c.z + x * c.w)); }
vec4 polyMul(vec4 a, vec4 b) { // degree <= 3 (two linear factors here)
    return vec4(a.x * b.x, a.x * b.y + a.y * b.x, a.x * b.z + a.y * b.y + a.z * b.x,
                a.x * b.w + a.y * b.z + a.z * b.y + a.w * b.x);
}
vec4 polyTimesX(vec4 a) { return vec4(0.0, a.x, a.y, a.z); }

// ∫∫ over (r ∩ part) of fx(x) fy(y) (integrateRect).
float integrateRect(vec4 r0, vec4 fx, vec4 fy) {
    vec4 r = vec4(max(r0.xy, vec2(0.0)), min(r0.zw, vec2(1.0)));
    if (rectEmpty(r)) return 0.0;
    float iy = polyIntegral(fy, r.y, r.w);
#if BLEND_PARTS == 8
    // Over [max(x0, y0), min(x1, y1)] the inner integral runs from y0 to x (degree 7 in x:
    // 4-point Gauss-Legendre is exact); beyond max(x0, y1) it is the full iy.
    float total = 0.0;
    float a = max(r.x, r.y), b = min(r.z, r.w);
    if (b > a) {
        const vec4 nodes = vec4(-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                0.8611363115940526);
        const vec4 weights = vec4(0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                  0.3478548451374538);
        float half_ = 0.5 * (b - a), mid = 0.5 * (a + b);
        for (int i = 0; i < 4; ++i) {
            float x = mid + half_ * nodes[i];
            total += half_ * weights[i] * polyEval(fx, x) * polyIntegral(fy, r.y, x);
        }
    }
    float from = max(r.x, r.w);
    if (r.z > from) total += polyIntegral(fx, from, r.z) * iy;
    return total;
#else
    return polyIntegral(fx, r.x, r.z) * iy;
#endif
}

// 1 + k (x - m), k = 12 (g - m) / W², clamped to stay >= 0 on [lo, hi].
vec4 linearWeight(float g, float m, float lo, float hi) {
    float w = hi - lo;
    if (!(w > 0.0)) return vec4(1.0, 0.0, 0.0, 0.0);
    float k = 12.0 * (g - m) / (w * w);
    if (m - lo > 0.0) k = min(k, 1.0 / (m - lo));
    if (hi - m > 0.0) k = max(k, -1.0 / (hi - m));
    return vec4(1.0 - k * m, k, 0.0, 0.0);
}

struct Density {
    float lambda;
    vec4 wx;
    vec4 wy;
};

Density densityOf(PartState s) {
    Density d;
    d.lambda = 0.0;
    d.wx = vec4(1.0, 0.0, 0.0, 0.0);
    d.wy = vec4(1.0, 0.0, 0.0, 0.0);
    const vec4 one = vec4(1.0, 0.0, 0.0, 0.0), x = vec4(0.0, 1.0, 0.0, 0.0);
    float b = integrateRect(s.rect, one, one);
    if (!(b > 0.0) || !(s.vCoef > 0.0)) return d;
    vec2 m = vec2(integrateRect(s.rect, x, one), integrateRect(s.rect, one, x)) / b;
    d.wx = linearWeight(s.mean.x, m.x, s.rect.x, s.rect.z);
    d.wy = linearWeight(s.mean.y, m.y, s.rect.y, s.rect.w);
    float mass = integrateRect(s.rect, d.wx, d.wy);
    d.lambda = mass > 0.0 ? s.vCoef * kPartArea / mass : 0.0;
    return d;
}
#endif

// blendPart: E = the estimated overlap, A_f <- max + (min - E) (never below either input, so a
// full part stays full), rectangle <- union (and the centroid of A_f g_f + A_s g_s - E g_E).
// Paper: E = (A_f / B_f) (A_s / B_s) b, clamped to min(A_f, A_s).
PartState blendPart(PartState f, PartState s) {
    vec4 both = vec4(max(f.rect.xy, s.rect.xy), min(f.rect.zw, s.rect.zw));
#if BLEND_CENTROID
    float e = 0.0;
    vec2 ge = vec2(0.5, 0.5);
    if (!rectEmpty(both)) {
        Density df = densityOf(f), ds = densityOf(s);
        vec4 px = polyMul(df.wx, ds.wx), py = polyMul(df.wy, ds.wy);
        float mass = integrateRect(both, px, py);
        if (mass > 0.0) {
            ge = vec2(integrateRect(both, polyTimesX(px), py),
                      integrateRect(both, px, polyTimesX(py))) / mass;
            e = clamp(df.lambda * ds.lambda * mass / kPartArea, 0.0, min(f.vCoef, s.vCoef));
        }
    }
#else
    float bf = rectArea(f.rect), bs = rectArea(s.rect);
    float b = rectArea(both);
    float df = bf > 0.0 ? min(1.0, f.vCoef * kPartArea / bf) : 0.0;
    float ds = bs > 0.0 ? min(1.0, s.vCoef * kPartArea / bs) : 0.0;
    float e = clamp(df * ds * b / kPartArea, 0.0, min(f.vCoef, s.vCoef));
#endif
    float sum = max(f.vCoef, s.vCoef) + (min(f.vCoef, s.vCoef) - e);
    PartState o;
    o.vCoef = clamp(sum, 0.0, 1.0);
    o.rect = rectUnite(f.rect, s.rect);
    o.mean = kPartCentroid;
#if BLEND_CENTROID
    if (sum > 1e-12)
        o.mean =
            rectClamp((f.vCoef * f.mean + s.vCoef * s.mean - e * ge) / sum, o.rect);
#endif
    return o;
}

// A state as stored (pack, unpack) and the final state's scalars of one part.
#if BLEND_BITS == 8
PartState quantise(PartState s) {
    s.vCoef = unpackUnorm8(packUnorm8(s.vCoef));
    s.rect = unpackRect8(packRect8(s.rect));
#if BLEND_CENTROID
    s.mean = vec2(unpackUnorm8(packUnorm8(s.mean.x)), unpackUnorm8(packUnorm8(s.mean.y)));
#endif
    return s;
}
PartState unpackFinal(uvec4 bits) {
    PartState s;
    s.rect = unpackRect8(bits.x);
    s.vCoef = unpackUnorm8(bits.y);
    s.mean = vec2(unpackUnorm8(bits.y >> 8u), unpackUnorm8(bits.y >> 16u));
    return s;
}
uvec4 packFinal(PartState s) {
#if BLEND_CENTROID
    uint coef = packUnorm8(s.vCoef) | (packUnorm8(s.mean.x) << 8u) |
                (packUnorm8(s.mean.y) << 16u);
#else
    uint coef = packUnorm8(s.vCoef);
#endif
    return uvec4(packRect8(s.rect), coef, 0u, 0u);
}
#else
vec4 unpackRect16(uvec2 bits) {
    return vec4(unpackUnorm16(bits.x), unpackUnorm16(bits.x >> 16u), unpackUnorm16(bits.y),
                unpackUnorm16(bits.y >> 16u));
}
uvec2 packRect16(vec4 r) {
    return uvec2(packUnorm16Down(r.x) | (packUnorm16Down(r.y) << 16u),
                 packUnorm16Up(r.z) | (packUnorm16Up(r.w) << 16u));
}
PartState quantise(PartState s) {
    s.vCoef = unpackUnorm16(packUnorm16(s.vCoef));
    s.rect = unpackRect16(packRect16(s.rect));
#if BLEND_CENTROID
    s.mean =
        vec2(unpackUnorm16(packUnorm16(s.mean.x)), unpackUnorm16(packUnorm16(s.mean.y)));
#endif
    return s;
}
PartState unpackFinal(uvec4 bits) {
    PartState s;
    s.rect = unpackRect16(bits.xy);
    s.vCoef = unpackUnorm16(bits.z);
    s.mean = vec2(unpackUnorm16(bits.z >> 16u), unpackUnorm16(bits.w));
    return s;
}
uvec4 packFinal(PartState s) {
#if BLEND_CENTROID
    uvec2 coef = uvec2(packUnorm16(s.vCoef) | (packUnorm16(s.mean.x) << 16u),
                       packUnorm16(s.mean.y));
#else
    uvec2 coef = uvec2(packUnorm16(s.vCoef), 0u);
#endif
    return uvec4(packRect16(s.rect), coef);
}
#endif

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
#if BLEND_PARTS == 1
    vec4 state = texelFetch(tState, px, 0);
    vec4 coverage = vec4(state.x, 0.0, 0.0, 0.0);
    vec4 windings = vec4(state.y, 0.0, 0.0, 0.0);
    vec4 momentX = vec4(state.z, 0.0, 0.0, 0.0);
    vec4 momentY = vec4(state.w, 0.0, 0.0, 0.0);
    vec4 bounds[SET_PARTS] = vec4[SET_PARTS](texelFetch(tBounds0, px, 0));
#else
    vec4 coverage = texelFetch(tCoverage, px, 0);
    vec4 windings = texelFetch(tWindings, px, 0);
#if BLEND_CENTROID
    vec4 momentX = texelFetch(tMomentX, px, 0);
    vec4 momentY = texelFetch(tMomentY, px, 0);
#else
    vec4 momentX = vec4(0.0), momentY = vec4(0.0);
#endif
    vec4 bounds[SET_PARTS] =
        vec4[SET_PARTS](texelFetch(tBounds0, px, 0), texelFetch(tBounds1, px, 0),
                        texelFetch(tBounds2, px, 0), texelFetch(tBounds3, px, 0));
#endif
    uvec4 final[FINAL_TARGETS];
    final[0] = texelFetch(tFinal0, px, 0);
    final[1] = texelFetch(tFinal1, px, 0);
#if FINAL_TARGETS == 4
    final[2] = texelFetch(tFinal2, px, 0);
    final[3] = texelFetch(tFinal3, px, 0);
#endif
    for (int k = 0; k < SET_PARTS; ++k) {
        PartState s = resolvePart(coverage[k], windings[k],
                                  vec4(bounds[k].xy, -bounds[k].zw), vec2(momentX[k], momentY[k]));
        // The silhouette's state as stored, then blended, then stored again.
#if BLEND_BITS == 8
        PartState f = unpackFinal(uvec4(final[0][k], final[1][k], 0u, 0u));
        uvec4 stored = packFinal(blendPart(f, quantise(s)));
        final[0][k] = stored.x;
        final[1][k] = stored.y;
#else
        PartState f = unpackFinal(uvec4(final[0][k], final[1][k], final[2][k], final[3][k]));
        uvec4 stored = packFinal(blendPart(f, quantise(s)));
        final[0][k] = stored.x;
        final[1][k] = stored.y;
        final[2][k] = stored.z;
        final[3][k] = stored.w;
#endif
    }
    oFinal0 = final[0];
    oFinal1 = final[1];
#if FINAL_TARGETS == 4
    oFinal2 = final[2];
    oFinal3 = final[3];
#endif
}
