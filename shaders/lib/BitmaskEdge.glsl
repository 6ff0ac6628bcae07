// wedges-bitmask: what one silhouette edge adds at one receiver P, shared by the wedge pass's
// fragment shader (wedge-bitmask.frag: one fragment per pixel and wedge, adds by image atomics)
// and the tiled evaluation (wedge-bitmask-tiles.comp: one invocation per pixel over its tile's
// list, adds in registers), so that both compute the same masks from the same arithmetic.
// The includer defines LIGHT_SAMPLE(i), light sample i of the light-samples table ((s, t, angle
// about the centre, quadrant of its run of 8), by angle: a storage buffer or a buffer texture),
// and BITMASK_SAMPLES (lib: shared/LightMask.h).
#ifndef PENUMBRA_LIB_BITMASK_EDGE_GLSL
#define PENUMBRA_LIB_BITMASK_EDGE_GLSL

#include "shared/Coverage.h"
#include "shared/LightMask.h"
#include "shared/Parts.h"

// The first sample whose angle is >= a (BITMASK_SAMPLES when none). The table after the
// samples (lib/Bindings.h LIGHT_SAMPLE_ANGLE_BINS) holds the first sample at or after each
// bin's start: the answer lies between the entries one bin below a's and two above (a bin off
// for the rounding of a's bin either way), and the bisection runs over those few samples only.
int firstAtOrAfter(float a) {
    int b = int(floor((a + 3.14159265359) * (float(LIGHT_SAMPLE_ANGLE_BINS) / 6.28318530718)));
    int lo = int(LIGHT_SAMPLE(BITMASK_SAMPLES + clamp(b - 1, 0, LIGHT_SAMPLE_ANGLE_BINS)).x);
    int hi = int(LIGHT_SAMPLE(BITMASK_SAMPLES + clamp(b + 2, 0, LIGHT_SAMPLE_ANGLE_BINS)).x);
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (LIGHT_SAMPLE(mid).z < a)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

CoverageLight frameCoverageLight() {
    CoverageLight light;
    light.c = frame.lightCenter.xyz;
    light.u = frame.lightU.xyz;
    light.v = frame.lightV.xyz;
    light.n = frame.lightN.xyz;
    light.uStar = frame.lightUStar.xyz;
    light.vStar = frame.lightVStar.xyz;
    return light;
}

#ifdef BITMASK_POTENTIAL
#include "lib/PotentialReceiver.glsl"

// One triangle's share of m_P(e): +1 when its third vertex lies on the far side of the plane
// through P and the edge from the light centre (crossing the edge's projection, a segment from P
// starts crossing the triangle), -1 on the centre's side (it stops), 0 without a triangle.
// sc: the centre's side, as sign(orient(P, e0, e1, c)). orient(P, a, b, c) = dot(a - P,
// (b - a) x (c - a)): the plane's normal from the triangle alone, so that far small triangles
// keep their sign. P in the triangle's plane (within float noise: P's own triangle, a coplanar
// neighbour) is taken a little towards the camera, as the stencil's polygon offset takes it
// (the visible side of a two-sided surface): the orientation of the eye instead.
// (triangleSide: the sign of orient(P, e0, e1, apex); triangleShare: its share given sc.)
// t: the triangle as lib/WedgeCorners.glsl's trianglePlane gives it: t[0] its first corner in
// ascending vertex-id order, w the sign that turns orient(P, corners) into orient(P, e0, e1,
// apex) (0: no triangle); t[1] the normal of the sorted corners.
int triangleSide(vec4 t[2], vec3 p) {
    if (t[0].w == 0.0) return 0;
    vec3 a = t[0].xyz;
    vec3 n = t[1].xyz;
    float d = t[0].w * dot(a - p, n);
    float tol = 4e-6 * length(n) * (length(a - p) + length(p));
    if (!(abs(d) > tol)) {
        vec3 eye = frame.eye.xyz;
        d = t[0].w * dot(a - eye, n);
        if (!(abs(d) > 4e-6 * length(n) * (length(a - eye) + length(eye)))) return 0;
    }
    return d > 0.0 ? 1 : -1;
}
int triangleShare(int side, float sc) {
    return side == 0 ? 0 : (side > 0) == (sc < 0.0) ? 1 : -1;
}
#endif

// Whether the edge adds anything at P, in two steps that a caller may run in separate loops
// (wedge-bitmask-tiles.comp: on a SIMD machine a branch costs whether or not a lane takes it,
// while a loop costs only the iterations some lane needs).
// bitmaskEdgeRegion: R for `light` as half-planes (h0, h1, h2; sg its orientation) and, with
// BITMASK_POTENTIAL, m = m_P(e) from the edge's triangles' planes tri0, tri1 (trianglePlane's);
// false where R misses the
// light, or (potential) where the edge is no silhouette seen from P (m = 0). Deterministic: run
// again with the same arguments it gives the same R.
bool bitmaskEdgeRegion(vec3 p, vec3 e0, vec3 e1,
#ifdef BITMASK_POTENTIAL
                       vec4 tri0[2], vec4 tri1[2], out int m,
#endif
                       CoverageLight light, out vec3 h0, out vec3 h1, out vec3 h2,
                       out float sg) {
    h0 = vec3(0.0);
    h1 = vec3(0.0);
    h2 = vec3(0.0);
    sg = 0.0;
#ifdef BITMASK_POTENTIAL
    m = 0;
    // The two triangles on opposite sides of the plane through P and the edge: no silhouette
    // seen from P, m = 0 whatever the centre's side (most pairs of most potential edges):
    // before the projection.
    int side0 = triangleSide(tri0, p);
    int side1 = triangleSide(tri1, p);
    if (side0 == -side1) return false;
#endif
    if (!edgeRegion(p, e0, e1, light, h0, h1, h2, sg)) return false;
#ifdef BITMASK_POTENTIAL
    // The centre's side of the plane through P and the edge: -sign(cr) sign(hp) from the same
    // projection that bounds R (R lies on the far side), so the two cannot disagree.
    float hp = dot(light.n, p - light.c);
    float sc = hp > 0.0 ? -sg : sg;
    m = triangleShare(side0, sc) + triangleShare(side1, sc);
    if (m == 0) return false; // no silhouette seen from P: D does not change across it
#endif
    return true;
}

// bitmaskEdgeSamples: the light samples R holds (shared/LightMask.h regionHolds), as bits of
// `words`, and their union `any`; false where R is empty after all (a sector of almost nothing,
// below): then the edge adds nothing, its area included.
bool bitmaskEdgeSamples(ivec2 px, vec3 h0, vec3 h1, vec3 h2, float sg, out uint words[8],
                        out uint any) {
    for (int w = 0; w < 8; ++w) words[w] = 0u;
    any = 0u;
#ifdef BITMASK_ROTATED
    // Shifted per pixel, the samples are in no order: every one is tested.
    vec2 shift = maskPixelShift(px);
    for (int w = 0; w < BITMASK_WORDS; ++w) {
        uint bits = 0u;
        for (int b = 0; b < 32; ++b) {
            vec2 y = maskShifted(LIGHT_SAMPLE(32 * w + b).xy, shift);
            if (regionHolds(h0, h1, h2, sg, y)) bits |= 1u << uint(b);
        }
        words[w] = bits;
        any |= bits;
    }
#else
    // The samples between the rays are a run of the angle-ordered pattern: from the first at
    // or after the sector's start, counter-clockwise, to the first at or after its end (a
    // sample on the start ray is in, on the end ray out: regionHolds' rule). The sector is
    // under pi: a span near 2 pi is the rounding of a sector of almost nothing (empty), one a
    // little over pi that of a sector of almost pi (the edge's line passing by the centre).
    // The rays' directions from their half-planes (h0 = sg (-q0.y, q0.x), h1 = sg (q1.y, -q1.x),
    // exact): counter-clockwise from q0 to q1 when sg > 0, from q1 to q0 otherwise.
    vec2 q0 = sg * vec2(h0.y, -h0.x);
    vec2 q1 = sg * vec2(-h1.y, h1.x);
    vec2 r0 = sg > 0.0 ? q0 : q1; // the start ray's direction
    vec2 r1 = sg > 0.0 ? q1 : q0; // the end ray's
    float from = atan(r0.y, r0.x);
    float to = atan(r1.y, r1.x);
    float span = to - from;
    if (span < 0.0) span += 6.28318530718;
    if (span > 4.71238898038) return false; // over 3 pi / 2: empty
    int first = firstAtOrAfter(from);
    int count = firstAtOrAfter(to) - first;
    if (count < 0) count += BITMASK_SAMPLES;
    // (The word is chosen by comparing with each constant index: a dynamic index into a
    // local array is a per-lane memory access on a SIMD machine, slower than the loop's test.)
    for (int k = 0; k < count; ++k) {
        int i = (first + k) & (BITMASK_SAMPLES - 1);
        vec2 y = LIGHT_SAMPLE(i).xy;
        uint bit = dot(h2, vec3(y, 1.0)) >= 0.0 ? 1u << uint(i & 31) : 0u;
        for (int w = 0; w < BITMASK_WORDS; ++w) words[w] |= (i >> 5) == w ? bit : 0u;
    }
    for (int w = 0; w < BITMASK_WORDS; ++w) any |= words[w];
#endif
    return true;
}

// Both steps: the light samples in the edge's region R seen from P as bits of `words`, their
// union `any`, R's half-planes and orientation; with BITMASK_POTENTIAL, m = m_P(e). False where
// the edge adds nothing at P.
bool bitmaskEdge(ivec2 px, vec3 p, vec3 e0, vec3 e1,
#ifdef BITMASK_POTENTIAL
                 vec4 tri0[2], vec4 tri1[2], out int m,
#endif
                 out CoverageLight light, out vec3 h0, out vec3 h1, out vec3 h2, out float sg,
                 out uint words[8], out uint any) {
    for (int w = 0; w < 8; ++w) words[w] = 0u;
    any = 0u;
    light = frameCoverageLight();
    if (!bitmaskEdgeRegion(p, e0, e1,
#ifdef BITMASK_POTENTIAL
                           tri0, tri1, m,
#endif
                           light, h0, h1, h2, sg))
        return false;
    return bitmaskEdgeSamples(px, h0, h1, h2, sg, words, any);
}

// Bit j of a byte to bit 4 j: a 1 in each 4-bit count whose sample the byte holds.
uint bitmaskLanes(uint byteBits) {
    uint lanes = (byteBits | (byteBits << 12u)) & 0x000F000Fu;
    lanes = (lanes | (lanes << 6u)) & 0x03030303u;
    return (lanes | (lanes << 3u)) & 0x11111111u;
}

// Checksums of one edge's adds (wedges-bitmask.md): the number of samples it adds to, and the
// same weighted by 1 + the count's place in its 32-bit word; times m, summed over the edges,
// the resolve compares them with the decoded counts: a count past [-8, 7] carries into its
// neighbour (or out of the word) and changes them. A word of mask bits holds four counts' words
// (a byte each, bit j the count at place j): place j's weight 1 + j is 1 + (j & 1) + (j & 2) +
// (j & 4), so the weighted sum is four population counts of the whole word, the masks repeated
// in every byte (a population count is a dozen instructions on a SIMD machine without one).
ivec2 bitmaskChecksums(uint words[8]) {
    int added = 0, weighted = 0;
    for (int w = 0; w < BITMASK_WORDS; ++w) {
        uint x = words[w];
        int c = bitCount(x);
        added += c;
        weighted += c + bitCount(x & 0xAAAAAAAAu) + 2 * bitCount(x & 0xCCCCCCCCu) +
                    4 * bitCount(x & 0xF0F0F0F0u);
    }
    return ivec2(added, weighted);
}

#endif // PENUMBRA_LIB_BITMASK_EDGE_GLSL
