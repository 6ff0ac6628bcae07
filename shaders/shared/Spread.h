// The order in which a dispatch's work groups take its items (tiles, pixels), so that each
// thread of a software rasteriser gets its share of the costly ones.
//
// llvmpipe runs a compute dispatch's work groups on its threads in contiguous blocks: with T
// threads, the first N / T groups on one, the next N / T on the next (lp_cs_tpool). Items listed
// in screen order cost alike where they lie close (the tiles of a penumbra, those of a lit
// floor): one thread would get the top of the frame, another the bottom, and the frame waits for
// the busier (measured on the sphere: 5 500 against 3 974 samples of the two threads' time).
// Group g takes item spreadIndex(g, n, k) = g k mod n instead, k near n times the golden ratio's
// fractional part (0.618...) and prime to n: a bijection of [0, n) (k has an inverse mod n) that
// sends any run of consecutive groups to items spread evenly over the list (the Kronecker
// sequence of 0.618...: its gaps take at most three lengths), so every thread, whatever their
// number, gets items from all over the frame. A GPU schedules its groups dynamically: the order
// changes nothing there but which neighbours share a cache.
#ifndef PENUMBRA_SHARED_SPREAD_H
#define PENUMBRA_SHARED_SPREAD_H

#include "Prelude.h"

SHARED_BEGIN

// The greatest common divisor of a and b.
SHARED_FN uint spreadGcd(uint a, uint b) {
    while (b != 0u) {
        uint r = a % b;
        a = b;
        b = r;
    }
    return a;
}

// k for n items: the integer nearest 0.618... n, then the next one prime to n (1 for n <= 2).
// Computed on the CPU (the shaders take k as a uniform): in GLSL the literal would be a float.
SHARED_FN uint spreadStride(uint n) {
    if (n <= 2u) return 1u;
    uint k = uint(double(n) * 0.6180339887498949 + 0.5);
    while (spreadGcd(k, n) != 1u) ++k;
    return k;
}

// Which of n items group g takes: g k mod n, exact in double (g, k < n < 2^26: g k < 2^52; the
// quotient's rounding cannot cross an integer, its fraction being 0 or at least 1 / n).
SHARED_FN uint spreadIndex(uint g, uint n, uint k) {
    double x = double(g) * double(k);
    double q = floor(x / double(n));
    return uint(x - q * double(n));
}

SHARED_END

#endif // PENUMBRA_SHARED_SPREAD_H
