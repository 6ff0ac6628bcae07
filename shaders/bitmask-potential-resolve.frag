// wedges-bitmask silhouettes=potential, after the one wedge pass: per pixel and sample, the
// count D(P, y) = D(P, c) (the stencil: the triangles the segment P -> c crosses, two-sided) plus
// the 4-bit count the wedges added (biased by 8, eight to a layer); a sample is hidden where D is
// non-zero. Writes V and the hidden samples' mask (Renderer::lightMasks).
// uEstimate 0 (estimate=ratio): occluded = A * S_u / S_s, A = D(P, c) + the wedges' sum of
// m_P(e) * area (the blended target: the exact integral of D over the light), S_u the share of
// hidden samples, S_s the mean of D over the samples; A where no sample is hidden; every sample
// hidden behind counts that differ: 1 (the ratio would only sample the layers' mix). Exact
// wherever D takes one non-zero value over the hidden part of the light, at any N. uEstimate 2
// (estimate=quadrants): the same per quadrant of the light, A_q from the wedges'
// per-quadrant target (shared/Parts.h regionQuadrantCoverage) and the own plane's share behind in
// the quadrant, S_u and S_s over the quadrant's samples (a 32-bit word of counts at a time: the
// light-samples table's w names each word's quadrant); the mean over the quadrants, each
// clamped; a quadrant none of whose samples is hidden takes the whole light's ratio. uEstimate 3
// (estimate=moments, the default; BITMASK_TILED only): quadrants, but where the hidden samples
// lie behind two or more layer counts, from the counts' exact first and second moments (below).
// uEstimate 1 (estimate=samples): occluded = S_u.
// The receiver's own plane: a light sample behind the plane of P's surface (the G-buffer's
// facet normal, facing the viewer) is hidden, as `raytrace` and `reference` count it. For a
// closed mesh the segment to it crosses the mesh itself and D already says so; for open and
// thin geometry — a level's walls, a quad — nothing else does, and the light behind a wall's
// plane would reach its front. The plane is one more layer: each such sample's D gains 1, and
// A gains the exact share of the light behind the plane (1 - horizonFraction), so the ratio
// estimator stays exact where the plane alone hides (A_h / 1) and where a closed mesh's far
// side does too (D = 1 + 1 over 2 A_h). Pixels where it hides some of the light are counted
// (MASK_STAT_OWN_PLANE).
// The two checksum layers after the counts (wedge-bitmask.frag) tell a count that did not fit
// its 4 bits: such a pixel is counted (MASK_STAT_OVERFLOW) and takes A alone, clamped. A pixel
// no wedge reached (the stencil's mark bit clear; with BITMASK_TILED, evaluate=tiles, the mark
// layer after the checksums) skips the counts.
#include "lib/Bindings.h"
#include "lib/Horizon.glsl"
#include "shared/Parts.h"

#ifndef BITMASK_SAMPLES
#define BITMASK_SAMPLES 64
#endif

layout(binding = IMAGE_GROUP_COUNTS, r32ui) uniform readonly uimage2DArray iCounts;
layout(binding = TEXUNIT_STENCIL) uniform usampler2D tStencil;
layout(binding = TEXUNIT_PARTS0) uniform sampler2D tArea; // per quadrant: the wedges' sum of m share
layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;
// The light samples ((s, t, angle about the centre, quadrant of its run), in count order) and the
// angle bins after them, as a uniform block (lib/Bindings.h BINDING_LIGHT_SAMPLES_UBO).
layout(std140, binding = BINDING_LIGHT_SAMPLES_UBO) uniform LightSampleTable {
    vec4 uLightSamples[BITMASK_SAMPLES + LIGHT_SAMPLE_ANGLE_BINS + 1];
};
layout(std430, binding = BINDING_MASK_STATS) buffer MaskStats {
    uint maskStats[];
};

layout(location = 0) uniform uint uEstimate;
// Each run of 8 samples' quadrant (the light-samples table's w, geometry::lightMaskRunQuadrants),
// 2 bits a run, runs 0-15 in x, 16-31 in y: a uniform, where the table read per run and lane
// was 3 % of the frame on data/box.json.
layout(location = 1) uniform uvec2 uRunQuadrants;

#ifdef BITMASK_TILED
// evaluate=tiles: drawn twice, split by a stencil of its own (bitmask-resolve-split.frag): this
// shader where a wedge added or the own plane may cut the light, BITMASK_RESOLVE_LIT elsewhere.
// The stencil test before the shader: a fragment it fails costs no shading.
layout(early_fragment_tests) in;
#endif

layout(location = 0) out float oVisibility;
layout(location = 1) out uvec4 oMask0;
#if BITMASK_SAMPLES > 128
layout(location = 2) out uvec4 oMask1;
#endif

// 1 for each sample behind P's own plane, as bits of `words` (and their number), if P has a
// surface and its plane crosses the light; `behindArea` the exact share behind, and
// `behindQuadrants` each quadrant's.
int ownPlane(ivec2 px, out uint words[8], out float behindArea, out vec4 behindQuadrants) {
    for (int w = 0; w < 8; ++w) words[w] = 0u;
    behindArea = 0.0;
    behindQuadrants = vec4(0.0);
    vec4 position = texelFetch(tPosition, px, 0);
    if (position.w == 0.0) return 0;
    vec3 N = texelFetch(tNormal, px, 0).xyz;
    float nc = dot(N, frame.lightCenter.xyz - position.xyz);
    float nu = dot(N, frame.lightU.xyz), nv = dot(N, frame.lightV.xyz);
    float front = horizonShare(nc, nu, nv);
    if (front >= 1.0) return 0;
    behindArea = 1.0 - front;
    // Per quadrant (signs (+,+), (-,+), (-,-), (+,-) of (s, t), as shared/Parts.h numbers them):
    // the quadrant is the square of half-size 1/2 about (sx / 2, sy / 2).
    int quadrants = front < 1.0 ? 4 : 0; // a bound, to skip the loop (below)
    for (int q = 0; q < quadrants; ++q) {
        vec2 sq = partsQuadrantSigns(q);
        behindQuadrants[q] =
            1.0 - horizonShare(nc + 0.5 * (sq.x * nu + sq.y * nv), 0.5 * nu, 0.5 * nv);
    }
    int behind = 0;
    // The bound, not the return above, skips the loop where the whole light is in front: on a
    // SIMD rasteriser (llvmpipe) every lane runs a branch, masked, whichever lanes take it, but
    // a loop ends once every lane has reached its bound (measured: 1.5 ms of a 4.5 ms resolve at
    // 256^2).
    // Each sample's bit into its word by comparing with each constant index: the word picked
    // by a per-lane index into a local array is a memory access per lane on a SIMD rasteriser
    // (this loop, with the samples read from a storage buffer: 2.9 % of the frame's
    // instructions on data/stability/light-grazing, whose shelf's faces cut the light).
    int n = front < 1.0 ? BITMASK_SAMPLES : 0;
    for (int i = 0; i < n; ++i) {
        vec2 st = uLightSamples[i].xy;
        bool hidden = nc + st.x * nu + st.y * nv <= 0.0;
        uint bit = hidden ? 1u << uint(i & 31) : 0u;
        for (int w = 0; w < BITMASK_SAMPLES / 32; ++w) words[w] |= (i >> 5) == w ? bit : 0u;
        behind += hidden ? 1 : 0;
    }
    atomicAdd(maskStats[MASK_STAT_OWN_PLANE], 1u);
    return behind;
}

#ifdef BITMASK_RESOLVE_LIT
// The pixels no wedge reached and whose own plane leaves the whole light in front: what main's
// untouched branch below gives them (ownPlane returns 0 there), and nothing else. Every D_i is
// D(P, c): all samples hidden or none.
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint stencil = texelFetch(tStencil, px, 0).r;
    int centre = int(stencil & 0x7Fu);
    if (centre >= 64) centre -= 128;
    if (centre < 0) atomicAdd(maskStats[MASK_STAT_NEGATIVE], 1u);
    float occluded = centre == 0 ? 0.0 : uEstimate == 1u ? 1.0 : float(sign(centre));
    uint words[8] = uint[8](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
    for (int w = 0; w < BITMASK_SAMPLES / 32; ++w) words[w] = centre != 0 ? 0xFFFFFFFFu : 0u;
    oVisibility = 1.0 - clamp(occluded, 0.0, 1.0);
    oMask0 = uvec4(words[0], words[1], words[2], words[3]);
#if BITMASK_SAMPLES > 128
    oMask1 = uvec4(words[4], words[5], words[6], words[7]);
#endif
}
#else
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint planeWords[8];
    float planeArea;
    vec4 planeQuadrants;
    int planeHidden = ownPlane(px, planeWords, planeArea, planeQuadrants);
    // The stencil's count bits (0-6, wrapping: a signed count in [-64, 63]; VolumeStates.h).
    uint stencil = texelFetch(tStencil, px, 0).r;
    int centre = int(stencil & 0x7Fu);
    if (centre >= 64) centre -= 128;
    uint words[8] = uint[8](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
#ifdef BITMASK_TILED
    // evaluate=tiles: the tiled evaluation's mark, in the layer after the checksums.
    bool touched = imageLoad(iCounts, ivec3(px, BITMASK_SAMPLES / 8 + 2)).r != 0u;
#else
    bool touched = (stencil & 0x80u) != 0u;
#endif
    if (!touched) {
        // No wedge fragment reached the pixel (the wedge pass marks the stencil's top bit): every
        // sample's D is D(P, c), no count was added and A is D(P, c). What the loop below
        // gives then, without reading the counts: all samples hidden or none, V 0 or 1.
        float occluded;
        if (centre != 0) {
            for (int w = 0; w < BITMASK_SAMPLES / 32; ++w) words[w] = 0xFFFFFFFFu;
            if (centre < 0) atomicAdd(maskStats[MASK_STAT_NEGATIVE], 1u);
            occluded = uEstimate == 1u ? 1.0 : float(sign(centre));
        } else {
            // Only the own plane hides: D = 1 over its samples, so the ratio is its area.
            for (int w = 0; w < BITMASK_SAMPLES / 32; ++w) words[w] = planeWords[w];
            occluded = uEstimate == 1u ? float(planeHidden) / float(BITMASK_SAMPLES) : planeArea;
        }
        oVisibility = 1.0 - clamp(occluded, 0.0, 1.0);
        oMask0 = uvec4(words[0], words[1], words[2], words[3]);
#if BITMASK_SAMPLES > 128
        oMask1 = uvec4(words[4], words[5], words[6], words[7]);
#endif
        return;
    }
    int hidden = 0;
    int sumD = 0, sumD2 = 0; // over the hidden samples: their layers, and its square
    ivec4 hiddenQ = ivec4(0), sumQ = ivec4(0);
    int leastD = 1 << 30, mostD = 0; // over the hidden samples
    uint added = 0u, weighted = 0u;
    bool negative = false;
    uint seen = 0u; // bit k: some hidden sample lies behind k layers (k = 31: 31 or more)
    // The layers to read: none where no wedge reached (returned above, but the lanes that
    // returned run what follows, masked, unless a loop's bound ends it; see ownPlane).
    int layers = touched ? BITMASK_SAMPLES / 8 : 0;
    for (int layer = 0; layer < layers; ++layer) {
        uint x = imageLoad(iCounts, ivec3(px, layer)).r;
        int hiddenRun = 0, sumRun = 0; // this word's 8 samples, all in one quadrant
        // The own plane's 8 bits for these samples in, the hidden ones out, as bytes: the
        // 32-bit word of the layer picked by comparing with each constant index (an index that
        // varies, into a local array, is a memory access per lane on a SIMD rasteriser:
        // measured, the resolve 5-25 % slower).
        uint planeWord = 0u;
        for (int k = 0; k < BITMASK_SAMPLES / 32; ++k)
            planeWord = k == (layer >> 2) ? planeWords[k] : planeWord;
        uint planeByte = (planeWord >> uint(8 * (layer & 3))) & 0xFFu;
        // The checksums' sums of the word's 8 counts (d_j = nibble j - 8): sum d_j and
        // sum (1 + j) d_j, by nibble sums within the word (j's bits split the places).
        uint odd = (x >> 4u) & 0x0F0F0F0Fu;
        uint pairs = (x & 0x0F0F0F0Fu) + odd;                // bytes: nibbles 2b + 2b + 1
        uint all8 = (pairs * 0x01010101u) >> 24u;           // sum over j of nibble j
        uint odds = (odd * 0x01010101u) >> 24u;             // over odd j
        uint mid = (pairs >> 8u) & 0x00FF00FFu;             // bytes 1 and 3: j in {2, 3, 6, 7}
        uint twos = (mid & 0xFFFFu) + (mid >> 16u);
        uint high = pairs >> 16u;                           // bytes 2 and 3: j in 4..7
        uint fours = (high & 0xFFu) + (high >> 8u);
        added += all8 - 64u;
        weighted += all8 + odds + 2u * twos + 4u * fours - 288u;
        // Per sample, without a branch (llvmpipe runs a branch's body for every lane, and each
        // assignment in it once more to mask it): layers = |D| + the own plane's bit is 0
        // exactly where the sample is lit, so the sums need no test; seen's bit 0, set by the
        // lit ones, is cleared after the words, and the least count skips them.
        uint hiddenByte = 0u;
        for (int j = 0; j < 8; ++j) {
            int D = centre + int((x >> uint(4 * j)) & 15u) - 8;
            int layers = abs(D) + int((planeByte >> uint(j)) & 1u);
            bool lit = layers == 0;
            hiddenByte |= lit ? 0u : 1u << uint(j);
            hiddenRun += lit ? 0 : 1;
            sumRun += layers;
            sumD2 += layers * layers;
            seen |= 1u << uint(min(layers, 31));
            leastD = min(leastD, lit ? 1 << 30 : layers);
            mostD = max(mostD, layers);
            negative = negative || D < 0;
        }
        hidden += hiddenRun;
        sumD += sumRun;
        for (int k = 0; k < BITMASK_SAMPLES / 32; ++k)
            words[k] |= k == (layer >> 2) ? hiddenByte << uint(8 * (layer & 3)) : 0u;
        // The word's quadrant (uRunQuadrants), one-hot: no dynamic index.
        uint runs = layer < 16 ? uRunQuadrants.x : uRunQuadrants.y;
        int q = int((runs >> uint(2 * (layer & 15))) & 3u);
        ivec4 inQ = ivec4(equal(ivec4(q), ivec4(0, 1, 2, 3)));
        hiddenQ += inQ * hiddenRun;
        sumQ += inQ * sumRun;
    }
    seen &= ~1u; // (set by lit samples, layers 0: no hidden sample's)
    bool overflow = added != imageLoad(iCounts, ivec3(px, BITMASK_SAMPLES / 8)).r ||
                    weighted != imageLoad(iCounts, ivec3(px, BITMASK_SAMPLES / 8 + 1)).r;
    // Per quadrant: D(P, c) + the wedges' m times the quadrant's share in R + the own plane's.
    vec4 areaQ = vec4(float(centre)) + texelFetch(tArea, px, 0) + planeQuadrants;
    float area = 0.25 * (areaQ.x + areaQ.y + areaQ.z + areaQ.w);
    float occluded;
    if (overflow) {
        occluded = area;
        atomicAdd(maskStats[MASK_STAT_OVERFLOW], 1u);
    } else if (uEstimate == 1u) {
        occluded = float(hidden) / float(BITMASK_SAMPLES);
    } else {
        // The ratio where it is exact or helps: one count over the hidden samples (A / D), or
        // several with some sample lit (a penumbra where layers overlap). With every sample
        // hidden behind layers of different counts, A / mean D would only be the sampling
        // error of the layers' mix, seen as light leaking into the umbra: the samples' share.
        bool mixedUmbra = hidden == BITMASK_SAMPLES && leastD != mostD;
        if (uEstimate >= 2u) {
            // estimate=quadrants: the same per quadrant, each with its exact integral; a
            // quadrant none of whose samples is hidden takes the whole light's ratio (1 where
            // none is: its integral alone, as above).
            float whole = sumD == 0 ? 1.0 : float(hidden) / float(sumD);
            vec4 ratioQ = mix(vec4(whole), vec4(hiddenQ) / vec4(max(sumQ, ivec4(1))),
                              greaterThan(sumQ, ivec4(0)));
            vec4 occQ = clamp(areaQ * ratioQ, 0.0, 1.0);
            occluded = mixedUmbra ? 1.0 : 0.25 * (occQ.x + occQ.y + occQ.z + occQ.w);
#ifdef BITMASK_TILED
            // estimate=moments: where the hidden samples lie behind two or more layer counts
            // d_i and nothing else (not the own plane) hides, the light splits into a_0 (lit)
            // and a_i (D = d_i), whose exact first and second moments are known: M1 = A and
            // M2 = D(P, c)^2 + 2 D(P, c) (A - D(P, c)) + the tiled pass's P. The samples' shares
            // of each count, moved the least (in the squared sense) to match both moments:
            // a = s - D^T (D D^T)^-1 (D s - M), D the 2 x k matrix of d_i and d_i^2. With two
            // counts this is the one exact solution, at any N, wherever no third count hides
            // some of the light unseen; with more it keeps what the samples say in the
            // directions the moments leave free. occluded = sum of a_i; one outside [0, 1]
            // says the moments and samples disagree: quadrants, as above.
            bool momentsGave = false;
            uint momentBits = uEstimate == 3u
                                  ? imageLoad(iCounts, ivec3(px, BITMASK_SAMPLES / 8 + 3)).r
                                  : WEDGE_TILES_NO_MOMENT;
            // (seen's bit 31 stands for every count from 31: such pixels keep quadrants.)
            if (uEstimate == 3u && bitCount(seen) >= 2 && (seen & 0x80000000u) == 0u &&
                planeHidden == 0 && planeArea == 0.0 && !negative &&
                momentBits != WEDGE_TILES_NO_MOMENT) {
                float c = float(centre);
                float m1 = area;
                float m2 = uintBitsToFloat(momentBits) + 2.0 * c * (area - c) + c * c;
                float union_;
                bool solved;
                if (bitCount(seen) == 2) {
                    // Two counts: a_1 + a_2 from d1 a_1 + d2 a_2 = M1, d1^2 a_1 + d2^2 a_2 = M2,
                    // in the well-conditioned closed form of the projection below.
                    float d1 = float(findLSB(seen)), d2 = float(findMSB(seen));
                    union_ = (m1 * (d1 + d2) - m2) / (d1 * d2);
                    solved = true;
                } else {
                    float n = float(BITMASK_SAMPLES);
                    float s0 = float(hidden) / n, s1 = float(sumD) / n, s2 = float(sumD2) / n;
                    // Over the counts present: sums of d, d^2, d^3, d^4.
                    float p1 = 0.0, p2 = 0.0, p3 = 0.0, p4 = 0.0;
                    for (uint rest = seen; rest != 0u; rest &= rest - 1u) {
                        float d = float(findLSB(rest));
                        p1 += d;
                        p2 += d * d;
                        p3 += d * d * d;
                        p4 += d * d * d * d;
                    }
                    float det = p2 * p4 - p3 * p3;
                    vec2 r = vec2(s1 - m1, s2 - m2);
                    vec2 lambda = vec2(p4 * r.x - p3 * r.y, p2 * r.y - p3 * r.x) / det;
                    union_ = s0 - (p1 * lambda.x + p2 * lambda.y);
                    solved = det > 0.0;
                }
                const float slack = 1e-3;
                if (solved && union_ >= -slack && union_ <= 1.0 + slack) {
                    occluded = union_;
                    momentsGave = true;
                    atomicAdd(maskStats[MASK_STAT_MOMENTS], 1u);
                }
            }
            if (uEstimate == 3u && bitCount(seen) >= 2 && !momentsGave)
                atomicAdd(maskStats[MASK_STAT_MOMENTS_FALLBACK], 1u);
#endif
        } else {
            occluded = sumD == 0 ? area
                       : mixedUmbra ? 1.0
                                    : area * float(hidden) / float(sumD);
        }
    }
    if (negative) atomicAdd(maskStats[MASK_STAT_NEGATIVE], 1u);
    oVisibility = 1.0 - clamp(occluded, 0.0, 1.0);
    oMask0 = uvec4(words[0], words[1], words[2], words[3]);
#if BITMASK_SAMPLES > 128
    oMask1 = uvec4(words[4], words[5], words[6], words[7]);
#endif
}
#endif // BITMASK_RESOLVE_LIT
