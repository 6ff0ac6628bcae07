// Final image: albedo * (ambient + (1 - ambient) * V * max(0, n.l)), sRGB encoded.
// V is the pure visibility fraction of DESIGN.md §2; n.l uses the direction to the light centre
// and the shading normal (the file's vertex normals, interpolated; else the face normal).
#include "lib/Bindings.h"

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_SHADING) uniform sampler2D tShading;
layout(binding = TEXUNIT_ALBEDO) uniform sampler2D tAlbedo;
layout(binding = TEXUNIT_VISIBILITY) uniform sampler2D tVisibility;

layout(location = 0) out vec4 oColor;

vec3 encodeSrgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(tPosition, px, 0);
    if (position.w == 0.0) {
        oColor = vec4(0.06, 0.07, 0.09, 1.0);
        return;
    }
    vec3 n = texelFetch(tShading, px, 0).xyz;
    vec3 albedo = texelFetch(tAlbedo, px, 0).rgb;
    float v = texelFetch(tVisibility, px, 0).r;
    vec3 l = normalize(frame.lightCenter.xyz - position.xyz);
    float ambient = frame.params.x;
    vec3 c = albedo * (ambient + (1.0 - ambient) * v * max(dot(n, l), 0.0));
    oColor = vec4(encodeSrgb(c * frame.params.z), 1.0);
}
