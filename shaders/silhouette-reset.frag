// Per-silhouette methods (GroupBatches.h, step 4): a batch's per-silhouette targets back to their
// empty values where its wedges touched; the stencil test selects those pixels and zeroes their
// stencil. Outputs past the framebuffer's attachments are dropped.
layout(location = 0) uniform vec4 uEmpty[8];

layout(location = 0) out vec4 oTarget[8];

void main() {
    for (int i = 0; i < 8; ++i) oTarget[i] = uEmpty[i];
}
