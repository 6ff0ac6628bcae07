// Shared by the debug views (gpu/src/engine/DebugViews.h): colours and the error heat ramp.

// Pixels without a surface in the views that replace the picture (visibility, stencil, parts,
// error keeps geometry::errorHeatMap's grey): a dark blue no value of theirs takes.
const vec3 kDebugNoSurface = vec3(0.10, 0.14, 0.35);

// geometry::heatColour (geometry/reference/src/ErrorImage.cpp), the same control points and arithmetic:
// t in [0, 1] (clamped; NaN saturates) → black, violet, red, orange, pale yellow. The caller
// writes it to an 8-bit target, which rounds as heatColour's lround(255 x) does.
vec3 debugHeatColour(float t) {
    const vec3 ramp[5] = vec3[5](vec3(0.00, 0.00, 0.00), vec3(0.35, 0.05, 0.55),
                                 vec3(0.85, 0.15, 0.30), vec3(1.00, 0.60, 0.05),
                                 vec3(1.00, 1.00, 0.70));
    t = isnan(t) || isinf(t) ? 1.0 : clamp(t, 0.0, 1.0);
    float x = t * 4.0;
    int i = min(int(x), 3);
    float f = x - float(i);
    return ramp[i] + f * (ramp[i + 1] - ramp[i]);
}
