// Shadow-volume geometry: w = 1 points (caps), w = 0 points at infinity (extruded away from the
// light on the CPU, geometry/shadow/ShadowVolume.h). The infinite projection maps w = 0 to depth 0.
#include "lib/Bindings.h"

layout(location = 0) in vec4 aPosition;

out float vFinite; // 1 for a point, 0 for a point at infinity

invariant gl_Position;

void main() {
    vFinite = aPosition.w;
    gl_Position = frame.viewProj * aPosition;
}
