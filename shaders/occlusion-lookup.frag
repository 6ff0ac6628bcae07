// Occlusion textures, lookup (Eisemann & Décoret 2006 §3.5): per G-buffer point P, every slice
// in front of it box-filtered over the kernel of eq. (4), combined as V = Π (1 - w_k I_k)
// (eq. 5). The box filter is one of (PREFILTER_*):
// - NBUFFERS: level l holds the mean over the 2^l × 2^l window starting at each texel (§3.2);
//   a window of side W in [2^l, 2^(l+1)] interpolates linearly between levels l and l + 1, each
//   read bilinearly at the window's corner (exact for power-of-two sides).
// - SAT: summed-area table, exact box over any rectangle (four corners, integer sums).
// - MIPMAPS: trilinear textureLod at log2(W) (aligned dyadic blocks: blocky, the comparison).
// Kernels under one texel are read as one texel (bilinear at the centre). The kernel's part
// outside the texture counts as empty: only casters inside the frustum were sliced.
// HORIZON (beyond the paper): V is also multiplied by the fraction of the light in front of the
// surface's plane (the side the camera sees), as one more independent occluder: surfaces turned
// from the light are dark in V, not only through the diffuse term.
// OUTSIDE_PCSS (outside=pcss): receivers the frustum does not cover are skipped; the pcss
// fallback after this pass writes them.
#include "lib/Bindings.h"
#include "lib/Occlusion.glsl"

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;
#ifdef PREFILTER_SAT
layout(binding = TEXUNIT_OCCLUSION) uniform usampler2DArray tSat;
#else
layout(binding = TEXUNIT_OCCLUSION) uniform sampler2DArray tSlices;
#endif

layout(location = 0) out float oVisibility;

#define TARGETS ((SLICES + 3) / 4)

#ifdef PREFILTER_NBUFFERS
// Mean over the window of side 2^level (texels) centred at c (texels), target t.
vec4 nbufferWindow(int level, int t, vec2 c) {
    float side = float(1 << level);
    vec2 corner = c - 0.5 * side; // the window starts here; level texel i starts at i
    vec2 uv = (corner + 0.5) * occlusion.texels.y;
    return texture(tSlices, vec3(uv, float(level * TARGETS + t)));
}

vec4 boxMean(int t, vec2 center, float width) {
    float R = occlusion.texels.x;
    float side = max(width * R, 1.0);
    vec2 c = center * R;
    int top = int(occlusion.texels.z);
    int level = min(int(floor(log2(side))), top);
    vec4 a = nbufferWindow(level, t, c);
    if (level == top) return a; // wider than the top level: the widest window built
    float base = float(1 << level);
    return mix(a, nbufferWindow(level + 1, t, c), clamp((side - base) / base, 0.0, 1.0));
}
#endif

#ifdef PREFILTER_MIPMAPS
vec4 boxMean(int t, vec2 center, float width) {
    float side = max(width * occlusion.texels.x, 1.0);
    return textureLod(tSlices, vec3(center, float(t)), log2(side));
}
#endif

#ifdef PREFILTER_SAT
// The SAT holds S(i, j) = Σ texels [0, i) × [0, j) for i, j in [0, R]; between lattice points
// the area integral is bilinear in S. Each corner is split into its lattice value (integers:
// the four corners' lattice values combine exactly) and small fractional terms, so that a
// kernel of a few texels keeps its precision far from the texture's origin (floats would lose
// it: S reaches R² = 262144 at R = 512).
struct SatCorner {
    ivec4 base; // S at the lattice point below-left
    vec4 frac;  // the bilinear remainder
};

SatCorner satCorner(int t, vec2 x) {
    int R = int(occlusion.texels.x);
    ivec2 i = min(ivec2(floor(x)), ivec2(R - 1));
    vec2 f = x - vec2(i);
    ivec4 s00 = ivec4(texelFetch(tSat, ivec3(i, t), 0));
    ivec4 s10 = ivec4(texelFetch(tSat, ivec3(i + ivec2(1, 0), t), 0));
    ivec4 s01 = ivec4(texelFetch(tSat, ivec3(i + ivec2(0, 1), t), 0));
    ivec4 s11 = ivec4(texelFetch(tSat, ivec3(i + ivec2(1, 1), t), 0));
    SatCorner c;
    c.base = s00;
    c.frac = f.x * vec4(s10 - s00) + f.y * vec4(s01 - s00) +
             f.x * f.y * vec4(s11 - s10 - s01 + s00);
    return c;
}

vec4 boxMean(int t, vec2 center, float width) {
    float R = occlusion.texels.x;
    float side = max(width * R, 1.0);
    vec2 lo = clamp(center * R - 0.5 * side, 0.0, R);
    vec2 hi = clamp(center * R + 0.5 * side, 0.0, R);
    if (hi.x <= lo.x || hi.y <= lo.y) return vec4(0.0);
    SatCorner a = satCorner(t, hi), b = satCorner(t, vec2(lo.x, hi.y)),
              c = satCorner(t, vec2(hi.x, lo.y)), d = satCorner(t, lo);
    vec4 sum = vec4(a.base - b.base - c.base + d.base) + (a.frac - b.frac - c.frac + d.frac);
    return sum / (side * side);
}
#endif

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(tPosition, px, 0);
    if (position.w == 0.0) {
        oVisibility = 1.0; // no surface
        return;
    }
#ifdef OUTSIDE_PCSS
    // A receiver the frustum does not cover: pcss's fallback lookup writes its V next (it runs
    // whenever the fit finds such receivers), so nothing here is worth computing.
    if (!occlusionCovers(position.xyz)) {
        oVisibility = 1.0;
        return;
    }
#endif
#ifdef HORIZON
    float horizon = horizonFraction(position.xyz, texelFetch(tNormal, px, 0).xyz);
#else
    float horizon = 1.0;
#endif
    if (occlusion.range.w != 0.0 || horizon == 0.0) {
        oVisibility = horizon; // nothing sliced, or the light wholly behind the surface
        return;
    }
    float zP = occlusionDepth(position.xyz);
    vec2 lateralP = occlusionLateral(position.xyz);
    float v = 1.0;
    for (int k = 0; k < SLICES; ++k) {
        SliceKernel s = occlusionKernel(zP, lateralP, k);
        if (s.weight <= 0.0) break; // weights only fall with k
        float occupied = boxMean(k >> 2, s.center, s.width)[k & 3];
        v *= 1.0 - s.weight * clamp(occupied, 0.0, 1.0);
        if (v <= 0.0) break; // umbra: the slices behind change nothing
    }
    oVisibility = horizon * v;
}
