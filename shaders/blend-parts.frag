// wedges-blend, per batch: resolve each quadrant's state of the batch's silhouette at P and blend
// it into the final state (Forest, Barthe & Paulin 2006, slides "Penumbra blending [4/6]-[6/6]";
// the arithmetic of geometry/BlendModel.h resolvePart, blendPart with Overlap::Paper, and its
// 8-bit packing). Drawn twice per batch, with the stencil selecting where the group's light
// centre is occluded (uCentre = 1) or not (0). The final state is read from the textures this
// pass writes: each pixel is written once per draw, after a texture barrier.
#include "lib/Bindings.h"

layout(binding = TEXUNIT_PARTS0 + 0) uniform sampler2D tCoverage;
layout(binding = TEXUNIT_PARTS0 + 1) uniform sampler2D tWinding0;
layout(binding = TEXUNIT_PARTS0 + 2) uniform sampler2D tWinding1;
layout(binding = TEXUNIT_PARTS0 + 3) uniform sampler2D tWinding2;
layout(binding = TEXUNIT_PARTS0 + 4) uniform sampler2D tBounds0;
layout(binding = TEXUNIT_PARTS0 + 5) uniform sampler2D tBounds1;
layout(binding = TEXUNIT_PARTS0 + 6) uniform sampler2D tBounds2;
layout(binding = TEXUNIT_PARTS0 + 7) uniform sampler2D tBounds3;
layout(binding = TEXUNIT_FINAL0) uniform usampler2D tFinalRect;
layout(binding = TEXUNIT_FINAL1) uniform usampler2D tFinalCoef;

layout(location = 0) uniform float uCentre; // 1: the group occludes the light centre here

layout(location = 0) out uvec4 oFinalRect;
layout(location = 1) out uvec4 oFinalCoef;

// --- 8-bit packing (BlendModel.cpp packUnorm8*, packRect8) ---
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

bool rectEmpty(vec4 r) { return r.x > r.z || r.y > r.w; }
float rectArea(vec4 r) { return rectEmpty(r) ? 0.0 : (r.z - r.x) * (r.w - r.y); }
vec4 rectExtend(vec4 r, vec2 p) {
    return rectEmpty(r) ? vec4(p, p) : vec4(min(r.xy, p), max(r.zw, p));
}
vec4 rectUnite(vec4 a, vec4 b) {
    if (rectEmpty(a)) return b;
    if (rectEmpty(b)) return a;
    return vec4(min(a.xy, b.xy), max(a.zw, b.zw));
}

// The silhouette's resolved state of quadrant q (resolvePart): vCoef and rectangle.
void resolvePart(float coverage, vec3 windings, vec4 edgeBounds, out float vCoef, out vec4 rect) {
    vCoef = clamp(uCentre + coverage, 0.0, 1.0);
    rect = vec4(1.0, 1.0, 0.0, 0.0);
    if (!(vCoef > 1e-6)) { // no occlusion: no rectangle
        vCoef = 0.0;
        return;
    }
    rect = edgeBounds;
    if (uCentre > 0.5) rect = rectExtend(rect, vec2(0.0, 0.0));
    if (uCentre + windings.x >= 0.5) rect = rectExtend(rect, vec2(1.0, 0.0));
    if (uCentre + windings.y >= 0.5) rect = rectExtend(rect, vec2(1.0, 1.0));
    if (uCentre + windings.z >= 0.5) rect = rectExtend(rect, vec2(0.0, 1.0));
}

// blendPart, Overlap::Paper: E = (A_f / B_f) (A_s / B_s) b, clamped to min(A_f, A_s).
void blendPart(inout float af, inout vec4 rf, float as, vec4 rs) {
    float bf = rectArea(rf), bs = rectArea(rs);
    vec4 both = vec4(max(rf.xy, rs.xy), min(rf.zw, rs.zw));
    float b = rectArea(both);
    float df = bf > 0.0 ? min(1.0, af / bf) : 0.0;
    float ds = bs > 0.0 ? min(1.0, as / bs) : 0.0;
    float e = clamp(df * ds * b, 0.0, min(af, as));
    float sum = max(af, as) + (min(af, as) - e);
    af = clamp(sum, 0.0, 1.0);
    rf = rectUnite(rf, rs);
}

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 coverage = texelFetch(tCoverage, px, 0);
    vec4 w0 = texelFetch(tWinding0, px, 0), w1 = texelFetch(tWinding1, px, 0),
         w2 = texelFetch(tWinding2, px, 0);
    vec3 windings[4] = vec3[4](w0.xyz, vec3(w0.w, w1.xy), vec3(w1.zw, w2.x), w2.yzw);
    vec4 bounds[4] = vec4[4](texelFetch(tBounds0, px, 0), texelFetch(tBounds1, px, 0),
                             texelFetch(tBounds2, px, 0), texelFetch(tBounds3, px, 0));
    uvec4 finalRect = texelFetch(tFinalRect, px, 0), finalCoef = texelFetch(tFinalCoef, px, 0);
    for (int q = 0; q < 4; ++q) {
        float as;
        vec4 rs;
        resolvePart(coverage[q], windings[q], vec4(bounds[q].xy, -bounds[q].zw), as, rs);
        // The silhouette's state as stored at 8 bits, then blended, then stored again.
        as = unpackUnorm8(packUnorm8(as));
        rs = unpackRect8(packRect8(rs));
        float af = unpackUnorm8(finalCoef[q]);
        vec4 rf = unpackRect8(finalRect[q]);
        blendPart(af, rf, as, rs);
        finalRect[q] = packRect8(rf);
        finalCoef[q] = packUnorm8(af);
    }
    oFinalRect = finalRect;
    oFinalCoef = finalCoef;
}
