// wedges-blend, after the last batch: V = 1 - mean over the four quadrants of the final state's
// occluded fractions (the quadrants have equal areas).
#include "lib/Bindings.h"

layout(binding = TEXUNIT_FINAL1) uniform usampler2D tFinalCoef;

layout(location = 0) out float oVisibility;

void main() {
    uvec4 coef = texelFetch(tFinalCoef, ivec2(gl_FragCoord.xy), 0) & 255u;
    oVisibility = 1.0 - float(coef.x + coef.y + coef.z + coef.w) / (4.0 * 255.0);
}
