// wedges-bitmask (GroupBatches.h, step 4): a batch's group masks back to empty where its wedges
// touched (the stencil test selects those pixels and zeroes their stencil).
layout(location = 0) out uvec4 oMask0;
layout(location = 1) out uvec4 oMask1; // dropped where the framebuffer has one target

void main() {
    oMask0 = uvec4(0u);
    oMask1 = uvec4(0u);
}
