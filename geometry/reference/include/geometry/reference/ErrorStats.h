// Per-pixel error of a visibility image against a reference (DESIGN.md §5).
#pragma once

#include <cstddef>
#include <span>

namespace geometry {

struct ErrorStats {
    std::size_t pixels = 0; // pixels where both images have a surface (finite values)
    std::size_t mismatchedCoverage = 0; // finite in one image, NaN in the other
    double meanAbs = 0.0;
    double rmse = 0.0;
    double p99 = 0.0;
    double max = 0.0;
    double badPixelPct = 0.0; // share of pixels with |error| > 0.05, in percent
};

// NaN in either image means "no surface" and is skipped (counted in mismatchedCoverage if only
// one side is NaN). Sizes must match (throws std::invalid_argument otherwise).
ErrorStats compareVisibility(std::span<const float> v, std::span<const float> reference);

// Temporal stability along a light path (DESIGN.md §5): the mean over consecutive frame pairs
// (k, k+1) of the mean over pixels of |(V[k+1] - V[k]) - (T[k+1] - T[k])|, V the method's frames
// and T the truth's of the same light positions. A pixel counts in a pair when it has a surface
// (finite) in all four images. 0 when the method changes exactly as the truth does, whatever its
// static error. Throws std::invalid_argument unless both have the same number (>= 2) of frames
// of one size.
double flicker(std::span<const std::span<const float>> frames,
               std::span<const std::span<const float>> truth);

} // namespace geometry
