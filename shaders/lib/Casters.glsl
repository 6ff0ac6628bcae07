// The casters' welded geometry (static) and the light centre's silhouettes (per frame), as
// uploaded by gpu/src/engine/CasterSet.cpp. Include after lib/Bindings.h.
layout(std430, binding = BINDING_WELDED_POSITIONS) readonly buffer WeldedPositions {
    vec4 weldedPositions[];
};
layout(std430, binding = BINDING_WELDED_INDICES) readonly buffer WeldedIndices {
    uint weldedIndices[];
};
layout(std430, binding = BINDING_CAP_TRIANGLES) readonly buffer CapTriangles {
    uint capTriangles[];
};
layout(std430, binding = BINDING_EDGES) readonly buffer Edges {
    GpuEdge edges[];
};
layout(std430, binding = BINDING_GROUPS) readonly buffer Groups {
    GpuGroup groups[];
};

// Corner k (0..2) of cap entry `entry`, in its light-oriented winding.
vec3 capCorner(uint entry, int k) {
    uint t = entry & ~CAP_FLIPPED;
    bool flipped = (entry & CAP_FLIPPED) != 0u;
    int corner = flipped && k != 0 ? 3 - k : k; // (a, b, c) or (a, c, b)
    return weldedPositions[weldedIndices[3u * t + uint(corner)]].xyz;
}
