// wedges-bitmask silhouettes=potential: the receiver its passes evaluate. Where the light's
// centre c lies in P's own plane (within float noise: a level's wall through a lamp hung at grid
// coordinates), every edge of that plane through P's surface has c on the plane through P and
// the edge, so the centre's side, and with it R and m_P(e), would be rounding noise, and the
// centre's volumes have side quads in that plane, as deep as P: a wall's front, lit by the half
// of the light in front of it, was drawn black in places. There P is taken RECEIVER_NUDGE of its
// distance to the eye towards the eye: by the wedge passes (potentialReceiver), and by the
// stencil, whose depth there is P's moved so before the centre's volumes are drawn
// (receiver-nudge.frag). Elsewhere P itself. surface-tiles.comp grows its tiles' bounds by as
// much.
#ifndef PENUMBRA_LIB_POTENTIAL_RECEIVER_GLSL
#define PENUMBRA_LIB_POTENTIAL_RECEIVER_GLSL

#define RECEIVER_NUDGE (1.0 / 4096.0)

// Whether c lies in the plane through p with normal n, up to the float noise of p.
bool planeHoldsLightCentre(vec3 p, vec3 n) {
    vec3 c = frame.lightCenter.xyz;
    return abs(dot(n, c - p)) <= 4e-6 * length(n) * (length(c - p) + length(p));
}

vec3 potentialReceiver(vec3 p, vec3 n) {
    return planeHoldsLightCentre(p, n) ? p + RECEIVER_NUDGE * (frame.eye.xyz - p) : p;
}

#endif
