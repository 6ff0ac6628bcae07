// The share of a rectangular light in front of a plane (geometry::horizonFraction, the shaders'
// lib/Horizon.glsl): an opaque surface hides the rest of the light from its own points. Pure
// functions, no bindings, GLSL and C++ alike (Prelude.h): the CPU runs these very statements.
//
// Over the light's square (s, t) in [-1, 1]^2 the signed distance to the plane is affine,
// g = a + b s + c t, and the share in front is P(g >= 0) for (s, t) uniform on the square. With
// B = max(|b|, |c|), C = min(|b|, |c|) the sum X = b s + c t is symmetric and its density is the
// trapezoid of two boxes of half-widths B and C (flat on |x| <= B - C, linear down to 0 at
// B + C), so P(X >= -a) = P(X <= a) = G(a) with, for y = |a|,
//     y >= B + C:          1
//     B - C < y < B + C:   1 - (B + C - y)^2 / (8 B C)
//     y <= B - C:          (y + B) / (2 B)
// and G(a) = that for a >= 0, 1 minus it below. Closed form and branch-free: on a SIMD
// rasteriser (llvmpipe runs both sides of a branch) the polygon clipping it replaces, with its
// small arrays, cost more than the rest of a resolve pixel. Each branch is finite where it is
// taken: the second only when C > 0 (its square is at most 4 C^2, so the quotient at most
// C / 2B), the third only when B > 0; a plane parallel to the light (B = C = 0) takes the first.
#ifndef PENUMBRA_SHARED_HORIZON_H
#define PENUMBRA_SHARED_HORIZON_H

#include "Prelude.h"

SHARED_BEGIN

// The share of the light's square where a + b s + c t >= 0.
SHARED_FN float horizonShare(float a, float b, float c) {
    float B = max(abs(b), abs(c)), C = min(abs(b), abs(c));
    float y = abs(a);
    float edge = B + C - y;
    float upper = y >= B + C    ? 1.0f
                  : y > B - C ? 1.0f - edge * edge / (8.0f * B * C)
                              : (y + B) / (2.0f * B);
    return a >= 0.0f ? upper : 1.0f - upper;
}

SHARED_END

#endif // PENUMBRA_SHARED_HORIZON_H
