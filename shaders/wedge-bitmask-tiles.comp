// wedges-bitmask silhouettes=potential evaluate=tiles: the wedge pass without rasterising the
// hulls. One work group per tile whose list is not empty (WEDGE_TILES_ACTIVE of them; the
// other pixels' mark layer is cleared before), one invocation per pixel of it, runs over the
// tile's list of wedges (wedge-tiles.comp) and
// adds what each edge adds at P (lib/BitmaskEdge.glsl, the fragment shader's own arithmetic)
// in registers; then writes what wedge-bitmask.frag's atomics and blending would have left:
// the biased 4-bit counts, the two checksums, per quadrant the sum of m times R's share
// (IMAGE_BITMASK_AREA), and whether any edge added (the raster pass's stencil mark), in the
// layer after the checksums. The area is summed in 64-bit fixed point (2^-29), so that the
// lists' order, which the binning's atomics decide, does not change it. With estimate=moments
// (uMoments), for the pixels that need P, the second moment of the wedges' sum over the light
// (those whose samples see two or more layer counts: few), the edges that added there into a
// slot of the moments buffer, and for every pixel the sentinel WEDGE_TILES_NO_MOMENT in the
// layer after the mark: wedge-moments.comp then computes P for the slots into that layer. (Here
// every pixel paid a pass of the pairs' loop, on a SIMD machine whether or not it needed it, and
// kept every region in local arrays indexed per lane: the frame's instructions, counted, 4 %
// more on bars-cross and on the sphere.)
#extension GL_ARB_shader_group_vote : require
#include "lib/Bindings.h"
#include "shared/WedgeHull.h"
#include "shared/Spread.h"

#ifndef BITMASK_SAMPLES
#define BITMASK_SAMPLES 64
#endif

layout(local_size_x = 8, local_size_y = 8) in; // one tile
#if WEDGE_TILE != 8
#error "a work group is one 8 x 8 tile"
#endif
#if MOMENT_EDGES % 4 != 0
#error "a moment slot's edges are stored four at a time"
#endif

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;
// The light samples ((s, t, angle about the centre, quadrant of its run), by angle) and the angle
// bins after them (lib/Bindings.h), as a uniform block (BINDING_LIGHT_SAMPLES_UBO).
layout(std140, binding = BINDING_LIGHT_SAMPLES_UBO) uniform LightSampleTable {
    vec4 uLightSamples[BITMASK_SAMPLES + LIGHT_SAMPLE_ANGLE_BINS + 1];
};
#define LIGHT_SAMPLE(i) uLightSamples[i]
layout(binding = IMAGE_GROUP_COUNTS, r32ui) uniform writeonly uimage2DArray iCounts;
layout(binding = IMAGE_BITMASK_AREA, rgba32f) uniform writeonly image2D iArea;
// estimate=moments: the stencil's D(P, c) (bits 0-6, signed), to find the pixels that need P.
layout(binding = TEXUNIT_STENCIL) uniform usampler2D tStencil;

#include "lib/BitmaskEdge.glsl"
#define WEDGE_TILES_TEXELS 1
#include "lib/WedgeTiles.glsl"

// The records and lists as buffer textures: llvmpipe fetches texels per SIMD vector, faster
// than its per-lane storage-buffer loads (this loop's cost).
layout(binding = TEXUNIT_WEDGE_TILE_RECORDS) uniform samplerBuffer tRecords;
layout(binding = TEXUNIT_WEDGE_TILE_LISTS) uniform usamplerBuffer tLists;

vec4 record(uint slot, int k) {
    return texelFetch(tRecords, int(slot) * TILE_WEDGE_TEXELS + k);
}
// TileWedge's fields by texel: e0 0 (and the kind), e1 1 (and eyeInside), planes 2-5, tri0 6-7,
// tri1 8-9, bound 10, tiles 11.

layout(location = 1) uniform ivec2 uTiles; // tiles across, down
layout(location = 2) uniform ivec2 uSize;  // the frame's pixels
// estimate=moments: also the regions for the second moment of the counts over the light
// (below), and the moment layer after the mark; 0: not computed.
layout(location = 4) uniform uint uMoments;

// estimate=moments keeps the regions of at most MOMENT_EDGES edges per pixel (lib/Bindings.h); a
// pixel with more gets no second moment (its resolve estimates by quadrants). Those that need P
// go to a slot of the moments buffer, while there are slots (uMomentSlots; the count of those
// that needed one is read back: a frame with more runs this pass again with room for all).
layout(std430, binding = BINDING_WEDGE_TILE_MOMENTS) writeonly buffer TileMoments {
    uvec4 tileMoments[]; // MOMENT_SLOT_UINTS / 4 per slot: the pixel, its edges' number, the edges
};
layout(location = 5) uniform uint uMomentSlots;
// spreadStride of the active tiles' number (shared/Spread.h).
layout(location = 6) uniform uint uSpread;

const float kAreaScale = 536870912.0; // 2^29: |m share| <= 2 fits a signed 32-bit step

// acc += x, as a 64-bit two's-complement integer (lo, hi).
void add64(inout uvec2 acc, int x) {
    uint lo = acc.x + uint(x);
    acc.y += (lo < acc.x ? 1u : 0u) + (x < 0 ? 0xFFFFFFFFu : 0u);
    acc.x = lo;
}
float value64(uvec2 acc) {
    return float(double(int(acc.y)) * 4294967296.0 + double(acc.x)) / kAreaScale;
}

void main() {
    int T = uTiles.x * uTiles.y;
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint activeTiles = heads[3 * T + WEDGE_TILES_ACTIVE];
    if (group >= activeTiles) return;
    // The active tiles are listed in about screen order: the group takes one from all over the
    // list (shared/Spread.h), so that each thread of a software rasteriser gets penumbra tiles.
    int tile = int(heads[3 * T + WEDGE_TILES_HEADER + spreadIndex(group, activeTiles, uSpread)]);
    // Invocation i's pixel: each run of 8 invocations (a SIMD vector on llvmpipe) a 4 x 2 block
    // of the tile rather than a row of 8, so that a vector's lanes lie closer together and share
    // more of their pairs (a loop runs as often as its busiest lane needs): on the sphere and
    // spheres-nine 1.4 % and 2.1 % fewer instructions per frame, 0.3-1.9 % on four other views.
    uint i = gl_LocalInvocationIndex;
    ivec2 inTile = ivec2(int((i >> 3u & 1u) * 4u + (i & 3u)), int((i >> 4u) * 2u + (i >> 2u & 1u)));
    ivec2 px = ivec2(tile % uTiles.x, tile / uTiles.x) * WEDGE_TILE + inTile;
    if (any(greaterThanEqual(px, uSize))) return;
    vec4 position = texelFetch(tPosition, px, 0);
    uint touched = 0u;
    if (position.w != 0.0) {
        vec3 p = potentialReceiver(position.xyz, texelFetch(tNormal, px, 0).xyz);
        vec3 eye = frame.eye.xyz;
        vec2 ndc = (vec2(px) + 0.5) / vec2(uSize) * 2.0 - 1.0;
        int t = tile;
        uint n = texelFetch(tLists, t).r, first = texelFetch(tLists, T + t).r;
        uint counts[BITMASK_SAMPLES / 8];
        for (int i = 0; i < BITMASK_SAMPLES / 8; ++i) counts[i] = 0x88888888u;
        int added = 0, weighted = 0;
        uvec2 area[4] = uvec2[4](uvec2(0u), uvec2(0u), uvec2(0u), uvec2(0u));
        uint pairs = 0u;
        // estimate=moments: every edge that added with a region that meets the light, as its
        // wedge slot and m (slot | (m + 2) << 29: the slots' records, 12 texels each, fit a
        // buffer texture), for P after the list (wedge-moments.comp computes their regions
        // again). In registers: written by comparing with each constant index (an index that
        // varies, into a local array, is a memory access per lane on a SIMD machine).
        uint regionEdges[MOMENT_EDGES];
        for (int k = 0; k < MOMENT_EDGES; ++k) regionEdges[k] = 0u;
        int regions = 0;
        float selfP = 0.0; // P's terms of the kept edges with themselves (wedge-moments.comp)
        bool momentsKept = uMoments != 0u;
        // The list in runs of 32, in three loops: the hull's front and back planes, where most
        // pairs end, as bits; then, for the set bits, the whole hull test (lib/WedgeTiles.glsl
        // tileWedgeHolds: the four planes again and a cut cone's far face; or a full-screen
        // wedge's rectangle), m_P(e) and whether R meets the
        // light (bitmaskEdgeRegion), where about half of the rest end, as bits and m's bit
        // planes; then for those only the samples, the area and the counts. On a SIMD machine
        // (llvmpipe: 8 pixels of a row a vector) each loop runs as often as its busiest lane
        // needs, not once per entry some lane needs, and a lane whose pair ends early idles
        // through the rest of the iteration: the loops' split keeps the costly part to the pairs
        // that add. Each run and entry counts 1 against the loop budget, each entry 2 more for
        // the second loop, each iteration of the third the most its loops may take (the samples
        // between two rays, two bisections).
        // The budget counts the iterations of the SIMD vector, which is what llvmpipe limits
        // (one counter per vector for all its loops), not one lane's: per run, the second loop
        // as the run's length (its bound whatever the lanes), the third as the most pairs any
        // invocation of the group adds (GL_ARB_shader_group_vote: the vector on llvmpipe, the
        // warp on a GPU), six votes a run. Votes cost: llvmpipe votes lane by lane (on the
        // sphere, against no votes, a vote per iteration of the two loops cost 6 % more
        // instructions, six a run 2 %; the third loop counted as the run's length, no votes,
        // while the budget allowed it spent the budget on nothing: the large light's view and
        // spheres-nine at 128² passed it). Counted per lane, a vector whose lanes' pairs fell
        // in different iterations ran past the limit while every lane stayed under its budget:
        // its loops cut silently, pairs lost, not counted (test
        // PotentialSilhouettes.TiledBudgetCountsTheVectorNotOneLane: 37 pixels off the raster
        // pass). Every lane of a vector now counts alike, so that their breaks agree.
        const int pairCost = BITMASK_SAMPLES + 2 * (findMSB(BITMASK_SAMPLES) + 2) + 4;
        const CoverageLight light = frameCoverageLight();
        int budget = WEDGE_TILES_LOOP_BUDGET;
        for (uint base = 0u; base < n; base += 32u) {
            uint run = min(32u, n - base);
            budget -= 1 + int(run);
            if (budget < 0) break;
            uint inside = 0u;
            for (uint j = 0u; j < run; ++j) {
                uint slot = texelFetch(tLists, int(uListBase + first + base + j)).r;
                // Two planes of four: two texels fewer a pair, in the loop that every entry of
                // the tile's list runs for every SIMD vector of it; the side planes cut few of
                // the pairs these keep (spheres-nine at 256²: 1.63 M pixel-wedge pairs pass
                // front and back, 1.35 M all four), and the second loop tests all four. (A
                // pixel's pairs the same: the frame's instructions 7 % fewer on spheres-nine,
                // 1-4 % on the box, the sphere, plates-three and the light grazing a plate.)
                vec4 front = record(slot, 2), back = record(slot, 3);
                if (!(dot(front.xyz, p) + front.w > 0.0) && !(dot(back.xyz, p) + back.w > 0.0))
                    inside |= 1u << j;
            }
            // m = +-1 or +-2 (the two triangles' shares): its sign and size as bit planes.
            uint adds = 0u, positive = 0u, double_ = 0u;
            // The second loop runs at most once per entry of the run, whatever the lanes.
            budget -= 2 * int(run);
            if (budget < 0) break;
            while (inside != 0u) {
                uint j = uint(findLSB(inside));
                inside &= inside - 1u;
                uint slot = texelFetch(tLists, int(uListBase + first + base + j)).r;
                // The rest of the hull test: a cut cone's far face, a full-screen wedge's
                // rectangle (its planes let every pixel through). (kind and eyeInside are
                // integers stored in the ends' w: compared as bits, 0 and 1 being zero and a
                // denormal.)
                vec4 e0 = record(slot, 0), e1 = record(slot, 1);
                uvec2 kind = floatBitsToUint(vec2(e0.w, e1.w));
                vec4 planes[4] = vec4[4](record(slot, 2), record(slot, 3), record(slot, 4),
                                         record(slot, 5));
                vec4 bound = record(slot, 10); // a cut cone's far face, a full-screen rectangle
                bool holds = kind.x == WEDGE_BOUNDED
                                 ? tileWedgeHolds(planes, bound, kind.y != 0u, eye, p)
                                 : all(greaterThanEqual(ndc, bound.xy)) && all(lessThanEqual(ndc, bound.zw));
                if (!holds) continue;
                vec4 tri0[2] = vec4[2](record(slot, 6), record(slot, 7));
                vec4 tri1[2] = vec4[2](record(slot, 8), record(slot, 9));
                vec3 h0, h1, h2;
                float sg;
                int m;
                if (!bitmaskEdgeRegion(p, e0.xyz, e1.xyz, tri0, tri1, m, light, h0, h1, h2, sg))
                    continue;
                adds |= 1u << j;
                positive |= m > 0 ? 1u << j : 0u;
                double_ |= abs(m) == 2 ? 1u << j : 0u;
            }
            // The third loop runs as often as the lane with the most pairs that add needs: that
            // number by votes on its bits, highest first.
            int adding = bitCount(adds), most = 0;
            for (int bit = 5; bit >= 0; --bit) {
                int trial = most | (1 << bit);
                if (anyInvocationARB(adding >= trial)) most = trial;
            }
            budget -= pairCost * most;
            if (budget < 0) break;
            while (adds != 0u) {
                uint j = uint(findLSB(adds));
                adds &= adds - 1u;
                uint slot = texelFetch(tLists, int(uListBase + first + base + j)).r;
                int m = (((double_ >> j) & 1u) != 0u ? 2 : 1) * (((positive >> j) & 1u) != 0u ? 1 : -1);
                // R again, as the loop above found it (the same statements).
                vec3 h0, h1, h2;
                float sg;
                edgeRegion(p, record(slot, 0).xyz, record(slot, 1).xyz, light, h0, h1, h2, sg);
                uint words[8];
                uint hit;
                if (!bitmaskEdgeSamples(px, h0, h1, h2, sg, words, hit)) continue;
                vec4 a = float(m) * regionQuadrantCoverage(h0, h1, h2);
                float share = 0.25 * (a.x + a.y + a.z + a.w);
                // (An edge whose R misses the light adds nothing to P: not kept.)
                if (momentsKept && share != 0.0) {
                    if (regions < MOMENT_EDGES) {
                        uint edge = slot | (uint(m + 2) << 29);
                        for (int k = 0; k < MOMENT_EDGES; ++k)
                            regionEdges[k] = k == regions ? edge : regionEdges[k];
                        ++regions;
                        selfP += float(m) * share; // m^2 |R ∩ L| / |L|: P's own terms
                    } else {
                        momentsKept = false;
                    }
                }
                for (int q = 0; q < 4; ++q) add64(area[q], int(round(a[q] * kAreaScale)));
                if (hit != 0u) {
                    ivec2 sums = bitmaskChecksums(words);
                    added += m * sums.x;
                    weighted += m * sums.y;
                }
                for (int wd = 0; wd < BITMASK_WORDS; ++wd)
                    for (int b = 0; b < 4; ++b) {
                        uint lanes = (words[wd] >> uint(8 * b)) & 0xFFu;
                        counts[4 * wd + b] += uint(m) * bitmaskLanes(lanes);
                    }
                ++pairs;
            }
        }
        // estimate=moments: P (wedge-moments.comp) is needed only by pixels whose samples see
        // two or more non-zero counts (the resolve uses it nowhere else): the counts are decoded
        // with D(P, c) first. The decoding's loop and the pairs' (at most MOMENT_EDGES^2 / 2,
        // in that pass) must fit what the list left of this pixel's budget; a pixel they would
        // not fit keeps no moment (its counts are complete: the frame stays tiled).
        const int countWords = BITMASK_SAMPLES / 8;
        int momentBudget =
            budget - countWords * (9 + countWords) - MOMENT_EDGES * (MOMENT_EDGES + 1) / 2;
        if (momentsKept && regions > 0 && momentBudget >= 0) {
            uint stencil = texelFetch(tStencil, px, 0).r;
            int centre = int(stencil & 0x7Fu);
            if (centre >= 64) centre -= 128;
            uint seen = 0u;
            // Word by word, as many as this pixel decodes: a loop of a constant count would be
            // unrolled, and on a SIMD machine, where a branch does not skip what it guards, every
            // pixel would pay the 64 samples' decoding (measured: 5-10 % of the evaluation on
            // the light grazing a plate); a loop whose count is 0 for every lane costs one pass
            // of its body.
            // The word is picked by comparing with each constant index (no dynamic array index).
            int decodeWords = momentsKept && regions > 0 && momentBudget >= 0 ? countWords : 0;
            for (int w = 0; w < decodeWords; ++w) {
                uint x = 0u;
                for (int k = 0; k < countWords; ++k) x = k == w ? counts[k] : x;
                for (int b = 0; b < 8; ++b) {
                    int D = centre + int((x >> uint(4 * b)) & 15u) - 8;
                    if (D != 0) seen |= 1u << uint(min(abs(D), 31));
                }
            }
            // (A count of 31 or more has no bit of its own: such pixels keep quadrants.)
            momentsKept = bitCount(seen) >= 2 && (seen & 0x80000000u) == 0u;
        }
        // The pixels that need P: the pixel and its edges into a slot for wedge-moments.comp
        // (the pairs' loop in a pass of its own, over those pixels only).
        bool needsMoment = momentsKept && regions > 0 && momentBudget >= 0;
        uint momentSlot = 0xFFFFFFFFu;
        if (needsMoment) momentSlot = atomicAdd(heads[3 * T + WEDGE_TILES_MOMENT_PIXELS], 1u);
        if (needsMoment && momentSlot < uMomentSlots) {
            // Four words a store, every edge word written (0 past `regions`): on a SIMD machine
            // each store is a loop over the lanes, run whether or not a lane stores.
            uint at = momentSlot * uint(MOMENT_SLOT_UINTS / 4);
            tileMoments[at] = uvec4(uint(px.x) | (uint(px.y) << 16), uint(regions),
                                    floatBitsToUint(selfP), 0u);
            for (int k = 0; k < MOMENT_EDGES / 4; ++k)
                tileMoments[at + 1u + uint(k)] =
                    uvec4(regionEdges[4 * k], regionEdges[4 * k + 1], regionEdges[4 * k + 2],
                          regionEdges[4 * k + 3]);
        }
        if (budget < 0) atomicAdd(heads[3 * T + WEDGE_TILES_TRUNCATED], 1u);
        if (pairs > 0u) {
            touched = 1u;
            for (int i = 0; i < BITMASK_SAMPLES / 8; ++i)
                imageStore(iCounts, ivec3(px, i), uvec4(counts[i]));
            imageStore(iCounts, ivec3(px, BITMASK_SAMPLES / 8), uvec4(uint(added)));
            imageStore(iCounts, ivec3(px, BITMASK_SAMPLES / 8 + 1), uvec4(uint(weighted)));
            imageStore(iArea, px, vec4(value64(area[0]), value64(area[1]), value64(area[2]),
                                       value64(area[3])));
            atomicAdd(heads[3 * T + WEDGE_TILES_PAIRS_ADDED], pairs);
        }
    }
    imageStore(iCounts, ivec3(px, BITMASK_SAMPLES / 8 + 2), uvec4(touched));
    // estimate=moments: no P yet (WEDGE_TILES_NO_MOMENT: no finite float has its bits);
    // wedge-moments.comp writes it for the pixels with a slot.
    if (uMoments != 0u)
        imageStore(iCounts, ivec3(px, BITMASK_SAMPLES / 8 + 3), uvec4(WEDGE_TILES_NO_MOMENT));
}
