// The share of the light in front of a surface's own plane (geometry::horizonFraction): an
// opaque surface hides the rest of the light from its points. Used by the occlusion and pcss
// lookups (parameter horizon=on) as one more independent occluder, and by wedges-bitmask's
// resolve as the receiver's own plane. The arithmetic is shared/Horizon.h's (closed form).
#ifndef PENUMBRA_HORIZON_GLSL
#define PENUMBRA_HORIZON_GLSL

#include "shared/Horizon.h"

// The fraction of the light in front of the plane through p with normal n.
float horizonFraction(vec3 p, vec3 n) {
    return horizonShare(dot(n, frame.lightCenter.xyz - p), dot(n, frame.lightU.xyz),
                        dot(n, frame.lightV.xyz));
}

#endif
