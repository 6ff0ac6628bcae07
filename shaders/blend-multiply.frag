// wedges-multiply: the final V times a batch's per-silhouette visibility, V = Π V_s (each
// silhouette treated as an independent occluder). Fixed-function blending does the product
// (DST_COLOR, ZERO); this writes clamp(V_s): one group alone is exact up to the wedges'
// own approximation, so the clamp only removes float noise.
#include "lib/Bindings.h"

layout(binding = TEXUNIT_SILHOUETTE) uniform sampler2D tSilhouette;

layout(location = 0) out float oVisibility;

void main() {
    oVisibility = clamp(texelFetch(tSilhouette, ivec2(gl_FragCoord.xy), 0).r, 0.0, 1.0);
}
