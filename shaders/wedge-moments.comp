// wedges-bitmask estimate=moments, after the tiled evaluation (wedge-bitmask-tiles.comp): P,
// the second moment of the wedges' sum over the light, for the pixels that need it (their
// samples see two or more layer counts), one invocation per pixel the evaluation gave a slot
// of the moments buffer (the pixel and the edges that added there with a region meeting the
// light, each as its wedge slot and m):
//   P = (1/|L|) integral over L of (sum over the edges of m times R's indicator)^2
//     = sum_e m_e^2 |R_e ∩ L| / |L| + 2 sum_{e < f} m_e m_f |R_e ∩ R_f ∩ L| / |L|,
// each R again as the evaluation computed it (the same statements on the same receiver, edge
// and light), the pairs' overlaps by shared/Parts.h partsRegionsOverlap. The first sum, each
// edge with itself, the evaluation adds up as it keeps the edges (the slot's third word): here
// it would take each edge's walk around the light's square again. With D(P, c) and A
// the resolve has the second moment of D from it. Written as bits into the moment layer (the
// layer after the mark), where the evaluation left WEDGE_TILES_NO_MOMENT. A pass of its own,
// over those pixels only: in the evaluation every pixel would pay a pass of the pairs' loop,
// on a SIMD machine whether or not it needs it.
#include "lib/Bindings.h"
#include "shared/WedgeHull.h"
#include "shared/Spread.h"

#ifndef BITMASK_SAMPLES
#define BITMASK_SAMPLES 64
#endif

layout(local_size_x = 64) in;

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;
// The light samples ((s, t, angle about the centre, quadrant of its run), by angle) and the angle
// bins after them (lib/Bindings.h), as a uniform block (BINDING_LIGHT_SAMPLES_UBO).
layout(std140, binding = BINDING_LIGHT_SAMPLES_UBO) uniform LightSampleTable {
    vec4 uLightSamples[BITMASK_SAMPLES + LIGHT_SAMPLE_ANGLE_BINS + 1];
};
#define LIGHT_SAMPLE(i) uLightSamples[i]
layout(binding = IMAGE_GROUP_COUNTS, r32ui) uniform writeonly uimage2DArray iCounts;

#include "lib/BitmaskEdge.glsl"

#define WEDGE_TILES_TEXELS 1
#include "lib/WedgeTiles.glsl"

// The wedges' records as texels (TileWedge: e0 texel 0, e1 texel 1).
layout(binding = TEXUNIT_WEDGE_TILE_RECORDS) uniform samplerBuffer tRecords;
vec4 record(uint slot, int k) {
    return texelFetch(tRecords, int(slot) * TILE_WEDGE_TEXELS + k);
}

layout(std430, binding = BINDING_WEDGE_TILE_MOMENTS) readonly buffer TileMoments {
    uint tileMoments[]; // MOMENT_SLOT_UINTS per slot (lib/Bindings.h)
};

layout(location = 0) uniform uint uSlots; // slots the evaluation filled
layout(location = 1) uniform uint uSpread; // spreadStride of the groups' number

void main() {
    // Rows of work groups (gl_NumWorkGroups.x wide), as the binning's place stage; each group
    // takes 64 slots from all over the list (shared/Spread.h: the slots are filled in about
    // screen order, and a pixel's cost is its number of edges).
    uint groups = (uSlots + 63u) / 64u;
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (group >= groups) return;
    uint slot = spreadIndex(group, groups, uSpread) * 64u + gl_LocalInvocationIndex;
    if (slot >= uSlots) return;
    uint at = slot * uint(MOMENT_SLOT_UINTS);
    uint pixel = tileMoments[at];
    ivec2 px = ivec2(pixel & 0xFFFFu, pixel >> 16);
    int regions = int(tileMoments[at + 1u]);
    vec3 p = potentialReceiver(texelFetch(tPosition, px, 0).xyz, texelFetch(tNormal, px, 0).xyz);
    const CoverageLight light = frameCoverageLight();
    // Each edge's R: its sector's rays (from, to), its line and m.
    vec4 regionSector[MOMENT_EDGES];
    vec3 regionLine[MOMENT_EDGES];
    int regionM[MOMENT_EDGES];
    for (int e = 0; e < regions; ++e) {
        uint edge = tileMoments[at + uint(MOMENT_SLOT_EDGES + e)];
        uint wedge = edge & 0x1FFFFFFFu;
        int m = int(edge >> 29) - 2;
        vec3 h0, h1, h2;
        float sg;
        edgeRegion(p, record(wedge, 0).xyz, record(wedge, 1).xyz, light, h0, h1, h2, sg);
        regionSector[e] = vec4(partsSectorFrom(h0, h1, sg), partsSectorTo(h0, h1, sg));
        regionLine[e] = h2;
        regionM[e] = m;
    }
    float sum = uintBitsToFloat(tileMoments[at + 2u]); // sum_e m_e^2 |R_e ∩ L| / |L|
    for (int e = 0; e < regions; ++e) {
        vec4 sectorE = regionSector[e];
        vec3 lineE = regionLine[e];
        int mE = regionM[e];
        for (int f = e + 1; f < regions; ++f)
            sum += 2.0 * float(mE * regionM[f]) *
                   partsRegionsOverlap(sectorE.xy, sectorE.zw, lineE, regionSector[f].xy,
                                       regionSector[f].zw, regionLine[f]);
    }
    imageStore(iCounts, ivec3(px, BITMASK_SAMPLES / 8 + 3), uvec4(floatBitsToUint(sum)));
}
