// linear-light-sm, skin pass: where the skin lies in front of the surface the target map holds
// (its depth zNear / z above the stored one by DEPTH_MARGIN), its value; blended by MIN into the
// target's skin layer (cleared to 2: no skin), so the darkest of overlapping skins stays.
#include "lib/Bindings.h"

layout(binding = TEXUNIT_SAMPLE_MAPS) uniform sampler2DArray tMaps;
layout(location = UNIFORM_SKIN_LAYERS) uniform ivec2 uLayers;

noperspective in float vValue;
layout(location = 0) out float oValue;

#define DEPTH_MARGIN 1e-3

void main() {
    float stored = texelFetch(tMaps, ivec3(ivec2(gl_FragCoord.xy), uLayers.y), 0).r;
    if (stored == 0.0 || gl_FragCoord.z <= stored * (1.0 + DEPTH_MARGIN)) discard;
    oValue = clamp(vValue, 0.0, 1.0);
}
