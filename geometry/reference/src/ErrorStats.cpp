// Error statistics of a visibility image against a reference (DESIGN.md §5).
#include <geometry/reference/ErrorStats.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace geometry {

namespace {
// DESIGN.md §3/§5: a pixel is "bad" when its error exceeds 0.05 (bad_pixel_pct in results.csv).
constexpr double kBadPixelThreshold = 0.05;
} // namespace

ErrorStats compareVisibility(std::span<const float> v, std::span<const float> reference) {
    if (v.size() != reference.size()) {
        throw std::invalid_argument("compareVisibility: image sizes differ (" +
                                    std::to_string(v.size()) + " vs " +
                                    std::to_string(reference.size()) + " values)");
    }
    ErrorStats stats;
    std::vector<double> errors;
    errors.reserve(v.size());
    double sumAbs = 0.0;
    double sumSq = 0.0;
    std::size_t bad = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
        // Non-finite means "no surface" (PFM images store NaN there).
        const bool haveV = std::isfinite(v[i]);
        const bool haveRef = std::isfinite(reference[i]);
        if (haveV != haveRef) ++stats.mismatchedCoverage;
        if (!haveV || !haveRef) continue;
        const double err = std::abs(static_cast<double>(v[i]) - static_cast<double>(reference[i]));
        errors.push_back(err);
        sumAbs += err;
        sumSq += err * err;
        stats.max = std::max(stats.max, err);
        if (err > kBadPixelThreshold) ++bad;
    }
    stats.pixels = errors.size();
    if (errors.empty()) return stats;

    const double n = static_cast<double>(errors.size());
    stats.meanAbs = sumAbs / n;
    stats.rmse = std::sqrt(sumSq / n);
    stats.badPixelPct = 100.0 * static_cast<double>(bad) / n;
    // Nearest-rank percentile: the smallest error that at least 99% of the pixels do not exceed.
    // Integer ceil(0.99 n): 0.99 is not exact in binary and would misplace the rank for n = 100.
    const std::size_t rank = (99 * errors.size() + 99) / 100;
    const auto nth = errors.begin() + static_cast<std::ptrdiff_t>(rank - 1);
    std::nth_element(errors.begin(), nth, errors.end());
    stats.p99 = *nth;
    return stats;
}

double flicker(std::span<const std::span<const float>> frames,
               std::span<const std::span<const float>> truth) {
    if (frames.size() != truth.size() || frames.size() < 2)
        throw std::invalid_argument("flicker: needs the same number (at least 2) of method and "
                                    "truth frames, got " + std::to_string(frames.size()) + " and " +
                                    std::to_string(truth.size()));
    const std::size_t n = frames[0].size();
    for (std::size_t k = 0; k < frames.size(); ++k)
        if (frames[k].size() != n || truth[k].size() != n)
            throw std::invalid_argument("flicker: frame " + std::to_string(k) +
                                        " differs in size from frame 0");
    double sum = 0.0;
    for (std::size_t k = 0; k + 1 < frames.size(); ++k) {
        const auto v0 = frames[k], v1 = frames[k + 1], t0 = truth[k], t1 = truth[k + 1];
        double pairSum = 0.0;
        std::size_t pixels = 0;
        for (std::size_t i = 0; i < n; ++i) {
            if (!std::isfinite(v0[i]) || !std::isfinite(v1[i]) || !std::isfinite(t0[i]) ||
                !std::isfinite(t1[i]))
                continue;
            const double dv = double(v1[i]) - double(v0[i]);
            const double dt = double(t1[i]) - double(t0[i]);
            pairSum += std::abs(dv - dt);
            ++pixels;
        }
        sum += pixels ? pairSum / double(pixels) : 0.0;
    }
    return sum / double(frames.size() - 1);
}

} // namespace geometry
