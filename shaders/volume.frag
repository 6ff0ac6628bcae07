// Stencil only: colour writes are off in this pass. The depth is clamped to the triangle's own
// depth range (volume.geom explains why).
flat in vec2 gDepthRange;

void main() {
    gl_FragDepth = clamp(gl_FragCoord.z, gDepthRange.x, gDepthRange.y);
}
