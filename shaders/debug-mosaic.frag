// Debug view "group-parts": one silhouette group's per-part visibility (TEXUNIT_DEBUG0: one
// part per channel, a set of at most four) as tiles of a uGrid x uGrid mosaic, each the whole
// view at 1 / uGrid scale, part k in tile uFirstTile + k (row-major from the top left). Tiles
// of other sets are left alone (discard). Grey = the part's visibility; no surface and the
// lines between tiles dark blue.
#include "lib/Bindings.h"
#include "lib/Debug.glsl"

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_DEBUG0) uniform sampler2D tParts;

layout(location = 0) uniform int uGrid;
layout(location = 1) uniform int uFirstTile;
layout(location = 2) uniform int uParts; // in this set

layout(location = 0) out vec4 oColor;

void main() {
    ivec2 size = textureSize(tParts, 0);
    vec2 g = gl_FragCoord.xy / vec2(size) * float(uGrid);
    ivec2 cell = min(ivec2(g), ivec2(uGrid - 1));
    int tile = (uGrid - 1 - cell.y) * uGrid + cell.x;
    int k = tile - uFirstTile;
    if (k < 0 || k >= uParts) discard;
    // A one-pixel line between tiles.
    vec2 tileSize = vec2(size) / float(uGrid);
    vec2 inTile = gl_FragCoord.xy - vec2(cell) * tileSize;
    if (uGrid > 1 && (inTile.x < 1.0 || inTile.y < 1.0)) {
        oColor = vec4(kDebugNoSurface, 1.0);
        return;
    }
    ivec2 src = min(ivec2((g - vec2(cell)) * vec2(size)), size - 1);
    if (texelFetch(tPosition, src, 0).w == 0.0) {
        oColor = vec4(kDebugNoSurface, 1.0);
        return;
    }
    oColor = vec4(vec3(texelFetch(tParts, src, 0)[k]), 1.0);
}
