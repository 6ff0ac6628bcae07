// wedges-multiply: the final V times a batch's per-silhouette visibility, V = Π V_s (each
// silhouette treated as an independent occluder). Fixed-function blending does the product
// (DST_COLOR, ZERO); this writes V_s = clamp(uLit - Σ coverage): uLit is 1 where the stencil
// says the group leaves the light centre visible, 0 where it occludes it, and the silhouette
// target holds minus the sum of its edges' coverage (0 where no wedge reached). One group alone
// is exact up to the wedges' own approximation, so the clamp only removes float noise.
#include "lib/Bindings.h"

layout(binding = TEXUNIT_SILHOUETTE) uniform sampler2D tSilhouette;

layout(location = 0) uniform float uLit;

layout(location = 0) out float oVisibility;

void main() {
    float sil = texelFetch(tSilhouette, ivec2(gl_FragCoord.xy), 0).r;
    oVisibility = clamp(uLit + sil, 0.0, 1.0);
}
