// PCSS, shadow pass: depth only; alpha-tested materials cut their texels out (lib/Material.glsl,
// the G-buffer's test), so leaves cast and the gaps between them do not.
#include "lib/Bindings.h"
#ifdef ALPHA_TEST
#include "lib/Material.glsl"
#endif

in vec2 vTexcoord;

void main() {
#ifdef ALPHA_TEST
    if (materialCutOut(materialTexel(vTexcoord))) discard;
#endif
}
