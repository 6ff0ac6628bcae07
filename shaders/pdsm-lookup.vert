// pdsm's lookup (pdsm-lookup.frag): fullscreen.vert's triangle, and the lookup's constants
// handed on as flat varyings. llvmpipe reads a uniform block lane by lane with a bounds check
// for each scalar (about 22 instructions per scalar per SIMD group of 8 pixels, measured: the
// light's nine scalars of horizonFraction cost 1.6 M of a 50 M frame on data/overlap.json at
// 256²), a flat varying once per triangle; the one map's lookup reads about 37 of them.
#include "lib/Bindings.h"

out vec2 vUv;
flat out vec3 fLightCentre, fLightU, fLightV; // the frame's light (the receiver's own plane)
flat out vec4 fCentre, fCube, fBasisU, fBasisV, fNormal; // PdsmUniforms' fields of those names
#ifdef ONE_MAP
flat out vec4 fFaceB1, fFaceB2, fFaceAxis, fFaceExtent, fFaceTexel; // face 0's
#else
// The cube's faces (their axes follow from the light's, pdsm-lookup.frag): per face k, its
// layer, zNear, sFar and texel size; its extent; its columns, rows and nearClipped flag.
flat out vec4 fFaceFrame[6], fFaceExtents[6], fFaceTexels[6];
#endif

void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    vUv = p;
    fLightCentre = frame.lightCenter.xyz;
    fLightU = frame.lightU.xyz;
    fLightV = frame.lightV.xyz;
    fCentre = pdsm.centre;
    fCube = pdsm.cube;
    fBasisU = pdsm.basisU;
    fBasisV = pdsm.basisV;
    fNormal = pdsm.normal;
#ifdef ONE_MAP
    fFaceB1 = pdsm.faceB1[0];
    fFaceB2 = pdsm.faceB2[0];
    fFaceAxis = pdsm.faceAxis[0];
    fFaceExtent = pdsm.faceExtent[0];
    fFaceTexel = pdsm.faceTexel[0];
#else
    for (int k = 0; k < 6; ++k) {
        fFaceFrame[k] = vec4(pdsm.faceB1[k].w, pdsm.faceB2[k].w, pdsm.faceAxis[k].w,
                             pdsm.faceTexel[k].x);
        fFaceExtents[k] = pdsm.faceExtent[k];
        fFaceTexels[k] = vec4(pdsm.faceTexel[k].yzw, 0.0);
    }
#endif
    gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
