// Adds the weight of one hard-shadow sample where the stencil says "lit" (the stencil test,
// EQUAL 0, does the selection; additive blending does the sum).
#include "lib/Bindings.h"

layout(location = 0) out float oVisibility;

void main() {
    oVisibility = frame.params.y;
}
