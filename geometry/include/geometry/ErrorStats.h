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

} // namespace geometry
