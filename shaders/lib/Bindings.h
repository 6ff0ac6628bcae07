// Binding slots and uniform-block layouts shared by C++ (gpu/src) and GLSL (shaders/).
// Valid as both languages: the C++ side gets structs with static_asserts on their std140 sizes,
// the GLSL side gets the uniform blocks, so the two cannot drift apart.
#ifndef PENUMBRA_BINDINGS_H
#define PENUMBRA_BINDINGS_H

#define BINDING_FRAME_UBO 0
#define BINDING_OCCLUSION_UBO 1 // OcclusionUniforms (the occlusion method's frame)
#define BINDING_PCSS_UBO 2      // PcssUniforms (the pcss method's maps and sample pattern)
#define BINDING_SAMPLE_MAPS_UBO 3 // SampleMapUniforms (the sample-maps method's frame)
// wedges-bitmask's tiled evaluation, moments pass and potential resolve: the light-samples table
// (the buffer of BINDING_LIGHT_SAMPLES) as a uniform block: llvmpipe reads a uniform per lane in
// about half the instructions of a buffer texel (the samples' loop: light-grazing 2.2 % of the
// frame's).
#define BINDING_LIGHT_SAMPLES_UBO 4
#define BINDING_PDSM_UBO 5 // PdsmUniforms (the pdsm method's deep map)

// Storage buffers (std430). Static: every caster's welded geometry, concatenated (CasterSet).
#define BINDING_WELDED_POSITIONS 0 // vec4 per welded vertex (w = 1)
#define BINDING_WELDED_INDICES 1   // 3 uint per welded triangle, global vertex ids
// Per frame, from the light centre's silhouettes (one upload, three ranges).
#define BINDING_CAP_TRIANGLES 2 // uint per group triangle: global triangle id | CAP_FLIPPED
#define BINDING_EDGES 3         // GpuEdge per directed silhouette edge copy
#define BINDING_GROUPS 4        // GpuGroup per silhouette group

// Per frame, on the GPU only (wedge methods).
#define BINDING_WEDGES 5      // GpuWedge per directed edge, built by shaders/wedge-setup.comp
#define BINDING_WEDGE_STATS 6 // uint counters (WEDGE_STAT_*)
#define BINDING_PCSS_STATS 7  // pcss: uint, receiver pixels outside both maps (lit)
#define BINDING_DEBUG_SUMS 8  // error debug view: vec2 per work group (sum |dV|, pixels)
#define BINDING_SURFACE_TILES 9 // per-silhouette methods: surface bounds per 16x16 tile (2 vec4)
#define BINDING_LIGHT_SAMPLES 10 // wedges-bitmask: vec4 per light sample (s, t, angle, 0)
// After the samples, LIGHT_SAMPLE_ANGLE_BINS + 1 vec4s whose x is the index of the first sample
// whose angle is at or after -pi + 2 pi b / LIGHT_SAMPLE_ANGLE_BINS (b = 0..bins; the last is
// the sample count): lib/BitmaskEdge.glsl firstAtOrAfter starts its bisection there.
#define LIGHT_SAMPLE_ANGLE_BINS 256
// wedges-bitmask silhouettes=potential (gpu/src/engine/PotentialSet.cpp): per entry of the
// edges array, the third vertices of its (at most two) triangles (global welded ids, or
// 0xFFFFFFFF), as uvec2.
#define BINDING_EDGE_APEXES 11
// wedges-bitmask silhouettes=potential: uint counters of the resolve (MASK_STAT_*).
#define BINDING_MASK_STATS 12
#define MASK_STAT_OVERFLOW 0 // pixels whose 4-bit counts did not hold the final count
#define MASK_STAT_NEGATIVE 1 // pixels with a sample whose count came out negative
#define MASK_STAT_OWN_PLANE 2 // pixels whose own plane hides part of the light (the resolve)
#define MASK_STAT_MOMENTS 3 // estimate=moments: pixels whose V the counts' moments gave
// estimate=moments: pixels whose samples see two or more layer counts but whose V the moments
// could not give (more edges than the tiled pass keeps, the own plane, a solution outside [0, 1])
#define MASK_STAT_MOMENTS_FALLBACK 4
#define MASK_STAT_COUNT 5
// sample-maps: per light sample, its view (SampleMapView: vec4 s, t and its lateral offset from
// the light's centre in (eu, ev); vec4 lo, 1 / (hi - lo)).
#define BINDING_SAMPLE_MAP_VIEWS 13
// sample-maps early_out=on: uint counters of the lookup (SAMPLE_MAP_STAT_*).
#define BINDING_SAMPLE_MAP_STATS 14
#define SAMPLE_MAP_STAT_EMPTY 0     // pixels in reach whose whole pyramid holds no caster
#define SAMPLE_MAP_STAT_QUADRANTS 1 // pixels that skipped the maps of some (not all) quadrants
#define SAMPLE_MAP_STAT_COUNT 2
// wedges-bitmask evaluate=tiles (gpu/src/passes/WedgeTilePass.h): per wedge slot a TileWedge
// (shaders/lib/WedgeTiles.glsl); the tiles' heads (per tile: count, first, cursor; then the
// total and the pass's counters: WEDGE_TILES_*) followed by the lists of wedge slots.
#define BINDING_WEDGE_TILE_RECORDS 15
#define BINDING_WEDGE_TILE_LISTS 16
#define BINDING_WEDGE_SUPERTILES 17 // the surface's bounds per 32 x 32 pixels (2 vec4)
// The count stage's entries as it finds them, 3 uints each (wedge slot, tile, index in the
// tile's list), while they fit the buffer: the place stage writes them into the lists without
// testing the tiles again.
#define BINDING_WEDGE_TILE_PAIRS 18
// estimate=moments: per pixel that needs P (its samples see two or more layer counts), the
// pixel (x | y << 16), the number of edges that added there with a region meeting the light,
// the sum over them of m^2 |R ∩ L| / |L| (float bits; a word of padding), and each one's wedge
// slot | (m + 2) << 29 (0 past the number), for
// shaders/wedge-moments.comp: written as MOMENT_SLOT_UINTS / 4 uvec4s.
#define BINDING_WEDGE_TILE_MOMENTS 19
#define MOMENT_EDGES 16 // edges a slot holds: a pixel where more add keeps no P (a multiple of 4)
#define MOMENT_SLOT_UINTS (4 + MOMENT_EDGES)
#define MOMENT_SLOT_EDGES 4 // the first edge's word in a slot
// pdsm: uint counters of the lookup (PDSM_STAT_*).
#define BINDING_PDSM_STATS 20
// tile-rects.vert: screen rectangles (vec4 NDC x0, y0, x1, y1 each), two triangles per
// rectangle: a full-screen pass drawn over some tiles only.
#define BINDING_SCREEN_RECTS 21
#define PDSM_STAT_OUTSIDE 0 // receivers outside a clipped deep map (drawn lit; may be hidden)
#define PDSM_STAT_COUNT 1
#define WEDGE_TILES_TOTAL 0        // list entries over all tiles (after the heads' 3 per tile)
#define WEDGE_TILES_PAIRS_ADDED 1  // (pixel, wedge) pairs that added to the counts
#define WEDGE_TILES_OVERFLOW 2     // 1: the total passed 2^32 - 1 (the lists cannot be held)
#define WEDGE_TILES_TRUNCATED 3    // invocations that stopped at WEDGE_TILES_LOOP_BUDGET
#define WEDGE_TILES_ACTIVE 4       // tiles with a non-empty list (their ids follow the header)
#define WEDGE_TILES_RECORDED 5     // entries the count stage found (recorded while they fit)
#define WEDGE_TILES_MOMENT_PIXELS 6 // estimate=moments: pixels whose regions the evaluation kept
                                   // for wedge-moments.comp (stored while they fit)
// Loop iterations one invocation of the tiled passes may run: Mesa's llvmpipe ends every loop of
// an invocation silently once their iterations add up to 65535 (gallivm's limit on loops), so a
// pass that could run longer counts its iterations, stops short of that and says so; the frame
// then rasterises its wedges instead.
#define WEDGE_TILES_LOOP_BUDGET 60000
// Slots per work group of wedge-tiles.comp's count and fill stages (WedgeTilePass dispatches
// that many fewer groups).
#define WEDGE_TILES_SLOT_GROUP 16
#define WEDGE_TILES_HEADER 7       // uints after the 3 per tile (then one per tile: the active ids)
// estimate=moments: the moment layer's value where the tiled pass kept no P (a NaN's bits, which
// floatBitsToUint of a finite P never gives; compared as bits, never as a float)
#define WEDGE_TILES_NO_MOMENT 0xFFFFFFFFu

#define IMAGE_VISIBILITY 0 // r32f image of V (resolve passes)
#define IMAGE_OCCLUSION_SRC 1 // occlusion: the prefilter's input (slices or N-buffer levels)
#define IMAGE_OCCLUSION_DST 2 // occlusion: the prefilter's output (N-buffer levels or SAT)
#define IMAGE_GROUP_COUNTS 3 // wedges-bitmask combine=counts: r32ui array, 8 biased 4-bit counts a layer
                             // (silhouettes=potential: then two checksum layers)
#define IMAGE_SAMPLE_MAP_NBUFFER 4 // sample-maps early_out=on: r32f array, the max N-buffer's levels
#define IMAGE_BITMASK_AREA 5 // wedges-bitmask evaluate=tiles: rgba32f, per quadrant the sum of m coverage

// Explicit uniform locations (plain uniforms set per draw).
#define UNIFORM_MATERIAL 0      // lib/Material.glsl: vec4 alpha cutoff, base alpha, textured
#define UNIFORM_MATERIAL_UV 1   // lib/Material.glsl: mat3 (locations 1..3)
#define UNIFORM_SLICE_LEAKFIX 4 // occlusion-slice.frag: int, 1 = also write the next slice
#define UNIFORM_PREFILTER_STEP 5 // occlusion prefilter, sample-maps N-buffer: int (level, SAT pass)
#define UNIFORM_PCSS_SIDE 6      // pcss-shadow.vert: int, the face drawn (PcssFrame::faces)
#define UNIFORM_SAMPLE_MAP_VIEW 7 // pcss-shadow.vert with SAMPLE_MAP: mat4 (locations 7..10)
// linear-light-skin.vert: the target map's projection (mat4, 11..14), the source map's layer and
// the target's (ivec2, 15), the source view's origin (vec3, 16) and extent lo, hi (vec4, 17),
// the maps' axes eu, ev, n (vec3, 18..20), zNear, zFar, R, the discontinuity ratio (vec4, 21)
#define UNIFORM_SKIN_TARGET_VIEW 11
#define UNIFORM_SKIN_LAYERS 15
#define UNIFORM_SKIN_ORIGIN 16
#define UNIFORM_SKIN_EXTENT 17
#define UNIFORM_SKIN_AXES 18
#define UNIFORM_SKIN_PARAMS 21
#define UNIFORM_FIRST_RECT 22 // tile-rects.vert: int, the first rectangle drawn

// GpuWedge::kind
#define WEDGE_BOUNDED 0u    // drawn as its conservative hull (8 triangles)
#define WEDGE_FULLSCREEN 1u // no bounded hull (edge line through the light): one triangle over
                            // the group's screen rectangle
#define WEDGE_DEGENERATE 2u // zero-length edge: changes nothing, draws nothing
#define WEDGE_CULLED 3u     // its group's influence misses the view frustum: draws nothing
// Counters in the wedge-stats buffer: one per kind, then pixels clamped by the resolve, then
// bounded wedges around the camera, then edges whose Fullscreen hull two silhouette cones
// replace (wedges-bitmask silhouettes=potential: wedgeHullSilhouetteCone).
#define WEDGE_STAT_CLAMPED 4
#define WEDGE_STAT_EYE_INSIDE 5
#define WEDGE_STAT_CONES 6
#define WEDGE_STAT_COUNT 8

#define CAP_FLIPPED 0x80000000u // light-oriented winding is (a, c, b) (geometry kTriangleFlipped)

#define TEXUNIT_POSITION 0
#define TEXUNIT_NORMAL 1
#define TEXUNIT_ALBEDO 2
#define TEXUNIT_VISIBILITY 3
#define TEXUNIT_SILHOUETTE 4 // a batch's per-silhouette visibility (per-silhouette methods)
#define TEXUNIT_PARTS0 5     // wedges-blend: a batch's per-part accumulation targets (5..12)
#define TEXUNIT_FINAL0 13    // wedges-blend: one set of parts' final packed state (13..16: 2
                             // targets at 8 bits, 4 at 16); the resolve: set k's vCoef at 13 + k
#define TEXUNIT_MATERIAL 17  // the drawn material's base-colour texture (G-buffer, slicing)
#define TEXUNIT_OCCLUSION 18 // occlusion: the prefiltered slices (N-buffers, mipmaps or SAT)
#define TEXUNIT_PCSS 19      // pcss: the shadow maps, one layer per face
#define TEXUNIT_DEBUG0 20    // debug views: their own inputs (reference, part visibility)
#define TEXUNIT_STENCIL 22   // wedges-bitmask combine=counts: the frame's stencil (STENCIL_INDEX view)
#define TEXUNIT_SHADING 23   // shade: the G-buffer's shading normal (the files' vertex normals)
#define TEXUNIT_SAMPLE_MAPS 24 // sample-maps: the shadow maps, one layer per light sample
#define TEXUNIT_SAMPLE_MAP_NBUFFER 25 // sample-maps early_out=on: the max N-buffer (layer = level)
#define TEXUNIT_WEDGE_TILE_RECORDS 26 // wedges-bitmask evaluate=tiles: the TileWedges as RGBA32F texels
#define TEXUNIT_WEDGE_TILE_LISTS 27   // the same: the tiles' heads and lists as R32UI texels
#define TEXUNIT_PDSM_INDEX 28 // pdsm: per deep-map texel (first point, point count), RG32UI, a layer per map
#define TEXUNIT_PDSM_DATA 29  // pdsm: the points, four per RGB32UI buffer texel (shared/Pdsm.h);
                              // deep-sm: its points, the same way
#define TEXUNIT_LINEAR_SKINS 31 // linear-light-sm: per end point's map, the skins' visibility
                               // ramp (R32F array; above 1.5: no skin)
#define TEXUNIT_DEEP_SM_INDEX 30 // deep-sm: per face (layer) and texel (first group, count |
                                 // nearest depth code << 16), RG32UI

#define PCSS_MAX_SAMPLES 64 // pcss: blocker-search and filter samples per pixel, at most
#define PCSS_REACH_BOXES 16 // pcss: boxes around the casters for the reach test

#ifdef __cplusplus
// C++ side: included through gpu/src/engine/ShaderBindings.h, which includes glm first (the GLSL
// loader resolves every #include itself, so this file includes nothing).
namespace gpu::shader {
using mat4 = glm::mat4;
using vec4 = glm::vec4;
using uint = std::uint32_t;
#define PENUMBRA_UBO_BEGIN(Name, slot) struct Name {
#define PENUMBRA_UBO_END(Name, instance) };
#else
#define PENUMBRA_UBO_BEGIN(Name, slot) layout(std140, binding = slot) uniform Name {
#define PENUMBRA_UBO_END(Name, instance) } instance;
#endif

// Per-frame constants. Only vec4/mat4 members so std140 and C++ layouts agree trivially.
PENUMBRA_UBO_BEGIN(FrameUniforms, BINDING_FRAME_UBO)
    mat4 viewProj;    // reversed-Z, infinite far plane (camera math in gpu/src/engine/Renderer.cpp)
    vec4 eye;         // xyz camera position
    vec4 lightCenter; // xyz centre of the rectangular light
    vec4 lightU;      // xyz half-axis u
    vec4 lightV;      // xyz half-axis v
    vec4 params;      // x: ambient term, y: accumulation weight, z: exposure, w: unused
    // The light's frame, derived once per frame (geometry/Wedge.cpp makeFrame): unit normal
    // along cross(u, v), and the dual basis s = dot(lightUStar, y - c), t = dot(lightVStar, ...).
    vec4 lightN;
    vec4 lightUStar;
    vec4 lightVStar;
PENUMBRA_UBO_END(FrameUniforms, frame)

// The occlusion method's frame (geometry/shadow/OcclusionSlices.h): the slicing frustum and slabs.
PENUMBRA_UBO_BEGIN(OcclusionUniforms, BINDING_OCCLUSION_UBO)
    mat4 sliceProj; // world -> clip of the slicing pass (OcclusionFrame::sliceProjection)
    vec4 axis;      // xyz: unit light normal towards the slices, w: COP distance d
    vec4 range;     // x: zNear, y: slice depth, z: slices, w: 1 if nothing is sliced (V = 1)
    vec4 texels;    // x: resolution R, y: 1 / R, z: top prefilter level built, w: unused
PENUMBRA_UBO_END(OcclusionUniforms, occlusion)

// The pcss method's frame (geometry/shadow/PcssFrame.h) and sample pattern: six faces around
// the light's centre (0: along n, 1: along -n, 2..5: along eu, -eu, ev, -ev).
PENUMBRA_UBO_BEGIN(PcssUniforms, BINDING_PCSS_UBO)
    mat4 shadowProj[6]; // world -> clip of each face's shadow pass (PcssFrame::projection)
    vec4 faceB1[6];     // xyz: the face's first lateral axis, w: 1 if receivers lie in it, + 2
                        // if its map is drawn
    vec4 faceB2[6];     // xyz: its second lateral axis, w: its casters' least depth (0: none)
    vec4 faceAxis[6];   // xyz: its depth axis, w: the light's greatest depth along it
    vec4 extent[6];     // per face: xy the map's lower corner lo in m = (x, y) / z, zw 1 / (hi - lo)
    vec4 lightU[6];     // xyz: the light's half axis along eu (halfSize.x eu) in face coordinates
    vec4 lightV[6];     // xyz: the same along ev
    vec4 basisU;        // xyz: the light's lateral axis eu, w: the front faces' cap maxTan
    vec4 basisV;        // xyz: the light's lateral axis ev, w: the maps drawn
    vec4 normal;        // xyz: the light's unit normal n, w: zNear
    vec4 params;        // x: blocker-search samples, y: filter samples, z: resolution R, w: 1 / R
    vec4 pattern[PCSS_MAX_SAMPLES]; // xy: filter pattern point i, zw: search point i, in [-1, 1]^2
    // Boxes holding the casters (geometry::casterClusters), each grown by the light's half
    // extent along each world axis: [2k] min, [2k + 1] max of box k; params2.x the boxes (0:
    // no test). A receiver whose segment to the light's centre misses every box has no segment
    // to any light point that meets a caster (PcssShadow::execute).
    vec4 reach[2 * PCSS_REACH_BOXES];
    vec4 params2;
    // deep-sm (DEEP_SHADOW_MAP): per face x: zc, the depth of code t = 0, y: sFar (t = 1 at
    // depth zc / sFar), z: 1 if its deep map is built (geometry::DeepShadowFace)
    vec4 faceDeep[6];
PENUMBRA_UBO_END(PcssUniforms, pcss)

// The sample-maps method's frame (geometry/shadow/SampleMapFrame.h); its views are in
// BINDING_SAMPLE_MAP_VIEWS.
PENUMBRA_UBO_BEGIN(SampleMapUniforms, BINDING_SAMPLE_MAPS_UBO)
    vec4 eu;     // xyz: the maps' first lateral axis
    vec4 ev;     // xyz: their second lateral axis
    vec4 n;      // xyz: their depth axis (the light's normal towards the casters)
    vec4 params; // x: samples N (0: no casters, V = 1), y: resolution R, z: bias (the offset's grazing part) in
                 // texels, w: zNear (every view's)
    vec4 reach;  // SampleMapFrame::centreLo (xy), centreHi (zw) (geometry::inReach)
    vec4 reachSpread; // xy: SampleMapFrame::half, z: 1 / zFar, w: 1 if reachAll
    // early_out=on (sample-maps-lookup.frag): x: the map k whose sample lies nearest the centre,
    // y: its N-buffer's levels (0: no early out), z: the receiver offset's largest share of
    // the receiver's depth, w: the texel footprints' margin in map coordinates (2.5 texels of
    // the widest map; the offset's shift is added per pixel from z)
    vec4 emptyTest;
    // Per quadrant of the light (its samples' st: x >= 0 adds 1, y >= 0 adds 2): xy the least,
    // zw the largest lateral offset d_i - d_k of its samples from sample k along eu, ev
    vec4 emptyQuadrant[4];
PENUMBRA_UBO_END(SampleMapUniforms, sampleMaps)

// The pdsm method's deep maps (geometry/shadow/PenumbraDeepShadowMap.h PdsmGrid), from the
// light's centre they were built for: one map along the light's normal, or one per face of the
// cube around the light (PdsmFace; faces numbered as pcss's, PcssFrame.h).
PENUMBRA_UBO_BEGIN(PdsmUniforms, BINDING_PDSM_UBO)
    // xyz: the light's centre the maps were built from (the frame's light while a moved light's
    // maps are being built in the background), w: 1 if a map holds casters (0: V = 1)
    vec4 centre;
    // x: 1 for the cube (a receiver's face picked by pcss's rule), 0 for one map (face 0),
    // y: the cube's front faces' cap tan, z: the receiver offset's grazing part in deep-map
    // texels (bias), w: resolution R
    vec4 cube;
    vec4 basisU; // xyz: the light's eu (the cube's rule), w: 1 if clipped (receivers outside
                 // a map counted)
    vec4 basisV; // xyz: the light's ev
    vec4 normal; // xyz: the light's normal, w: the cube's zNear (nearer to the centre: lit)
    vec4 faceB1[6];     // xyz: face's first lateral axis, w: its layer of the index, -1: none
    vec4 faceB2[6];     // xyz: its second lateral axis, w: zNear (its casters' least depth)
    vec4 faceAxis[6];   // xyz: its depth axis, w: sFar
    vec4 faceExtent[6]; // xy: lo in m = (x, y) / z, zw: 1 / (hi - lo)
    // x: a texel's world size per unit of depth (the larger side's), yz: the face's columns and
    // rows (a side face's band fills the first rows of its R x R layer), w: 1 if a caster may
    // lie nearer than its zNear (PdsmGrid::nearClipped: a receiver nearer may be hidden, counted)
    vec4 faceTexel[6];
PENUMBRA_UBO_END(PdsmUniforms, pdsm)

// One directed silhouette edge copy from the light centre: the group's light-oriented
// triangles lie to the left of v0 -> v1 seen from the light (geometry/shadow/Silhouette.h).
struct GpuEdge {
    uint v0;    // global welded vertex ids
    uint v1;
    uint group; // global group index (GpuGroup)
    uint flags; // reserved, 0
};

// One silhouette group (geometry::SilhouetteGroup) with global ranges.
struct GpuGroup {
    vec4 influenceMin; // xyz: conservative bounds of where the group changes visibility
    vec4 influenceMax;
    uint firstEdge;
    uint edgeCount;
    uint firstTriangle;
    uint triangleCount;
};

// One penumbra wedge as the GPU draws it: the edge and its conservative hull
// E + cone(rays) (geometry/shadow/WedgeHull.h, shaders/shared/WedgeHull.h).
struct GpuWedge {
    vec4 e0;        // xyz: edge start (light-oriented triangles to the left of e0 -> e1)
    vec4 e1;        // xyz: edge end
    vec4 planes[4]; // hull planes: front, back, side at e0, side at e1; P is inside when
                    // dot(planes[i].xyz, P) + planes[i].w <= 0 for all four
    vec4 rays[4];   // xyz: the hull's directions at infinity g1..g4; a silhouette cone cut to
                    // its receivers (WedgeHull::cone, reach): w of rays[0..2] its apex,
                    // rays[3].w its reach (> 0; 0 for every other hull)
    uint kind;      // WEDGE_*
    uint group;
    uint eyeInside; // 1: the camera may be inside the hull (drawn by its exit faces)
    uint edge;      // the edge's index in the edges array (a twin slot's is another's)
};

#ifdef __cplusplus
static_assert(sizeof(GpuWedge) == 176, "GpuWedge must match std430");
static_assert(sizeof(GpuEdge) == 16, "GpuEdge must match std430");
static_assert(sizeof(GpuGroup) == 48, "GpuGroup must match std430");
static_assert(sizeof(FrameUniforms) == 64 + 8 * 16, "FrameUniforms must match std140");
static_assert(sizeof(OcclusionUniforms) == 64 + 3 * 16, "OcclusionUniforms must match std140");
static_assert(sizeof(SampleMapUniforms) == 11 * 16, "SampleMapUniforms must match std140");
static_assert(sizeof(PcssUniforms) == 6 * 64 + (6 * 7 + 4 + PCSS_MAX_SAMPLES + 2 * PCSS_REACH_BOXES + 1) * 16,
              "PcssUniforms must match std140");
} // namespace gpu::shader
#endif

#endif
