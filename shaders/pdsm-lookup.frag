// pdsm, lookup: V at each G-buffer point P from the penumbra deep shadow map
// (geometry/shadow/PenumbraDeepShadowMap.h): P is projected from the light's centre into the
// deep map (the one map, or its face's of the cube around the light, picked by pcss's rule:
// geometry::PcssFrame::faceOf), and the visibility functions of the 2 x 2 texels around its ray are read at P's
// depth code t (shared/Pdsm.h, the statements geometry::evaluatePdsm runs) and weighted
// bilinearly, so that V changes continuously as P moves across texels.
// - A surface does not hide its own points: the sample maps store every surface 1.5 texels of
//   its depth slope farther from their sample (PdsmMethod.cpp kMapSlopeBias), and each of the
//   four texels is read where its ray meets P's tangent plane (below). And P is moved along
//   its normal, to the side it faces, by bias tan(a) texels of the deep map at P's depth (a:
//   the angle between the normal and the direction to the centre, tan(a) capped at 8;
//   shared/Pdsm.h pdsmOffsetReceiver): a surface the light grazes is narrower in the maps than
//   a texel, whose stored depth is then the surface beside it (a stair's riser under its
//   tread's nose, a crate's side under its top). Default 0.05 (256², against reference N =
//   1024: oa_dm5's spawn view with the lamp 0.0044 mean error with none, 0.0024 with it, no
//   data/ scene worse by more than 0.0001; bias 0.1 costs spheres-nine 0.0002 and 0.25
//   plates-three 0.0006: every texel of offset lifts the receiver towards its casters and
//   lightens its penumbrae; before the receiver plane and the maps' offset, the walls of
//   data/demo.json grazed by the light were striped dark, 0.046). Until this offset moved
//   receivers to the side they face, a receiver facing away from the light's centre was moved
//   into the object behind it (a crate's side lit by the light's edge came out dark).
// - Nearer to the light than every caster (t < 0), lit; past the deepest receiver the map was
//   built for (t > 1), the last value.
// - Outside the deep map's extent: lit. Where the map was clipped (casters reaching the light's
//   plane or past the maps' cap) such a receiver may be hidden: counted (PDSM_STAT_OUTSIDE).
// - OWN_PLANE (plane=on): V is at most the share of the light in front of P's plane (the
//   receiver hides the rest, as `raytrace` counts it). A minimum, not a product: the samples
//   behind the plane are often also hidden in the maps (the surface P lies on is a caster
//   there), and the deep map keeps only how many samples are hidden, not which.
// - The constants (the light, PdsmUniforms' fields, the faces' numbers) come as flat varyings
//   from pdsm-lookup.vert, which says why; in the cube, a face's picked per pixel by selects,
//   its axes derived from the light's (PdsmMethod checks that the built faces have them).
#include "lib/Bindings.h"
#include "lib/Pdsm.glsl"
#include "shared/Horizon.h"

flat in vec3 fLightCentre, fLightU, fLightV;
flat in vec4 fCentre, fCube, fBasisU, fBasisV, fNormal;
#ifdef ONE_MAP
flat in vec4 fFaceB1, fFaceB2, fFaceAxis, fFaceExtent, fFaceTexel;
#else
flat in vec4 fFaceFrame[6], fFaceExtents[6], fFaceTexels[6];
#endif

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;
layout(binding = TEXUNIT_PDSM_INDEX) uniform usampler2DArray tIndex; // first point, count

layout(std430, binding = BINDING_PDSM_STATS) buffer PdsmStats {
    uint pdsmStats[PDSM_STAT_COUNT];
};

layout(location = 0) out float oVisibility;

#ifndef RECEIVER_PLANE_SPAN
#define RECEIVER_PLANE_SPAN 16.0
#endif

// The cube face whose map holds a point at toP from the centre (geometry::PcssFrame::faceOf),
// -1 within the cube's zNear of the centre.
int cubeFace(vec3 toP) {
    float x = dot(toP, fBasisU.xyz), y = dot(toP, fBasisV.xyz);
    float z = dot(toP, fNormal.xyz);
    float a = max(abs(x), abs(y));
    if (a <= fCube.y * abs(z)) return abs(z) > fNormal.w ? (z > 0.0 ? 0 : 1) : -1;
    if (a <= fNormal.w) return -1;
    if (abs(x) >= abs(y)) return x >= 0.0 ? 2 : 3;
    return y >= 0.0 ? 4 : 5;
}

// The face's frame: the one map's (ONE_MAP); in the cube, the face picked per pixel, its axes
// those of pcss's faces (geometry::fitPcssFrame: 0 and 1 along ±n with (eu, ev); 2 and 3
// along ±eu with (ev, n); 4 and 5 along ±ev with (eu, n)), its numbers chosen among the six
// by selects (an array read per lane is a read lane by lane; from the uniform block it took
// 3 M of the lookup's 31 M instructions per frame on data/overlap.json at 256²).
struct PdsmFace {
    vec4 b1, b2, axis, extent, texel;
};
#ifndef ONE_MAP
vec4 pickFace(vec4 a0, vec4 a1, vec4 a2, vec4 a3, vec4 a4, vec4 a5, int k) {
    return k == 0 ? a0 : k == 1 ? a1 : k == 2 ? a2 : k == 3 ? a3 : k == 4 ? a4 : a5;
}
#define PDSM_PICK(a, k) pickFace(a[0], a[1], a[2], a[3], a[4], a[5], k)
#endif
PdsmFace pdsmFace(int face) {
#ifdef ONE_MAP
    return PdsmFace(fFaceB1, fFaceB2, fFaceAxis, fFaceExtent, fFaceTexel);
#else
    vec3 axis = face < 2 ? fNormal.xyz : face < 4 ? fBasisU.xyz : fBasisV.xyz;
    axis = (face & 1) != 0 ? -axis : axis;
    vec3 b1 = face == 2 || face == 3 ? fBasisV.xyz : fBasisU.xyz;
    vec3 b2 = face < 2 ? fBasisV.xyz : fNormal.xyz;
    vec4 frame = PDSM_PICK(fFaceFrame, face);
    vec4 texel = PDSM_PICK(fFaceTexels, face);
    return PdsmFace(vec4(b1, frame.x), vec4(b2, frame.y), vec4(axis, frame.z),
                    PDSM_PICK(fFaceExtents, face), vec4(frame.w, texel.xyz));
#endif
}

// Written without early returns: llvmpipe runs every statement for every SIMD group whatever
// the branches decide (only a loop's extra iterations are skipped), and each return became
// masks and masked stores around the rest; `shaded` says instead whether the pixel reads the
// map, and its texels' counts are zero where it does not (data/overlap.json at 256²: 0.8 M of
// 31 M instructions per frame).
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(tPosition, px, 0);
    vec3 P = position.xyz;
    vec3 N = texelFetch(tNormal, px, 0).xyz;
    vec3 c = fCentre.xyz; // the map's light (the frame's, but while the next is built)
#ifdef OWN_PLANE
    // The share of the frame's light in front of P's plane (lib/Horizon.glsl's horizonFraction).
    float front = horizonShare(dot(N, fLightCentre - P), dot(N, fLightU), dot(N, fLightV));
#else
    float front = 1.0;
#endif
    // Not read: no surface (V = 1), no casters, the whole light behind P's plane (V = front).
    bool shaded = position.w != 0.0 && fCentre.w != 0.0 && front != 0.0;
#ifdef ONE_MAP
    int face = 0;
#else
    int face = cubeFace(P - c);
    shaded = shaded && face >= 0; // within the cube's zNear of the centre: lit
    face = max(face, 0);
#endif
    PdsmFace fr = pdsmFace(face);
    float layer = fr.b1.w;
    shaded = shaded && layer >= 0.0; // a face with no receivers or no casters
    vec3 eu = fr.b1.xyz, ev = fr.b2.xyz, n = fr.axis.xyz;
    float zNear = fr.b2.w, sFar = fr.axis.w, R = fCube.w;
    vec4 extent = fr.extent;
    float texelSize = fr.texel.x;
    vec2 faceSize = fr.texel.yz; // the face's columns and rows (of the R x R layer)
    // The offset along P's normal (shared/Pdsm.h).
    vec3 Q = pdsmOffsetReceiver(P, N, c, dot(P - c, n), fCube.z, texelSize);
    vec3 d = Q - c;
    float z = dot(d, n);
    // Nearer to the light than the face's zNear: lit. Nearer than every caster, unless zNear was
    // held beyond one (texel.w: a caster nearer than the samples' own depth along the face's
    // axis, a shelf under the light, a wall just behind it); then such a receiver may be
    // hidden: counted below with those outside the map.
    bool beforeNear = z <= zNear;
    bool mayBeHidden = shaded && beforeNear && fr.texel.w != 0.0;
    shaded = shaded && !beforeNear;
    vec2 uv = (vec2(dot(d, eu), dot(d, ev)) / z - extent.xy) * extent.zw;
#ifndef ONE_MAP
    // In the cube, P's face holds it; the offset may carry Q a little past the face's edge.
    uv = clamp(uv, vec2(0.0), vec2(1.0));
#endif
    bool outside = any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)));
    // (A probe of the one map counts only those outside its extent, below.)
    mayBeHidden = mayBeHidden && fBasisV.w == 0.0;
#ifdef COUNT_OUTSIDE
    // Compiled in only where the maps are clipped (else none is counted): llvmpipe runs the
    // atomic, masked, for every SIMD group (1.2 M of a 50 M frame on data/overlap.json at 256²).
    if ((shaded && outside && fBasisU.w != 0.0) || mayBeHidden)
        atomicAdd(pdsmStats[PDSM_STAT_OUTSIDE], 1u);
#endif
    // A probe of the one map's extent before it is built (basisV.w) counts only.
    shaded = shaded && !outside && fBasisV.w == 0.0;
    // The 2 x 2 texels around Q's ray (two gathers: first groups and counts), weighted
    // bilinearly; a texel without points is lit. Each texel's function is read no deeper than
    // where its ray meets Q's tangent plane (the receiver plane): a surface the light grazes (a
    // wall beside the light, a tilted plate) crosses the neighbouring rays up to a texel times
    // tan(a) nearer than Q's depth, and read at Q's depth those rays would find the surface
    // itself in front of Q. Never deeper than Q's own depth: in a concave corner (a floor
    // meeting a wall) a neighbouring ray meets Q's plane behind the wall (kaos2's first spawn
    // view with the lamp: dark lines along the wall's foot, 0.0068 mean error, 0.0007 without).
    // The plane's depth is held within RECEIVER_PLANE_SPAN texels of Q's (a ray nearly in the
    // plane meets it far away). As a loop of four only where one of the four holds a function:
    // llvmpipe runs a loop's body once for a SIMD group even where no lane enters it (masked),
    // and the other three times only for groups near a function.
    vec2 x = uv * faceSize - 0.5;
    vec2 base = floor(x);
    vec2 f = x - base;
    vec2 gather = (base + 1.0) / R;
    uvec4 firsts = textureGather(tIndex, vec3(gather, layer), 0);
    uvec4 counts = shaded ? textureGather(tIndex, vec3(gather, layer), 1) : uvec4(0u);
    vec4 w = vec4((1.0 - f.x) * f.y, f.x * f.y, f.x * (1.0 - f.y), (1.0 - f.x) * (1.0 - f.y));
    // The gathered texels' columns and rows (x: (i0, j1), y: (i1, j1), z: (i1, j0), w: (i0, j0)).
    vec4 ci = base.x + vec4(0.5, 1.5, 1.5, 0.5), cj = base.y + vec4(1.5, 1.5, 0.5, 0.5);
    vec2 texelM = 1.0 / (faceSize * extent.zw); // a texel's size in m
    float planeD = dot(N, d);                  // the plane through Q: dot(N, X - c) = planeD
    vec3 Nm = vec3(dot(N, eu), dot(N, ev), dot(N, n));
    float span = RECEIVER_PLANE_SPAN * texelSize * z;
    float v = 0.0;
    int texels = any(notEqual(counts, uvec4(0u))) ? 4 : 0;
    for (int k = 0; k < texels; ++k) {
        // Texel k's ray c + zk (m_k, 1) meets the plane at zk = planeD / dot(N, (m_k, 1))
        // (shared/Pdsm.h pdsmReadDepth).
        vec2 mk = extent.xy + vec2(ci[k], cj[k]) * texelM;
        float tk = pdsmDepthCode(pdsmReadDepth(Nm, planeD, mk, z, span, zNear), zNear, sFar);
        v += w[k] * (counts[k] == 0u ? 1.0 : pdsmFunction(firsts[k], counts[k], tk));
    }
    if (texels == 0) v = 1.0;
    oVisibility = position.w == 0.0 ? 1.0 : shaded ? min(v, front) : front;
}
