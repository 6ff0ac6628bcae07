// Jittered-stratified samples on [-1, 1]^2 for the light integral (DESIGN.md §2, §4 "Reference").
#include <geometry/core/Sampling.h>

#include <stdexcept>

namespace geometry {

namespace {

// SplitMix64 (Steele, Lea & Flood 2014). Written out here rather than using <random>
// distributions, whose output differs between standard libraries: the GPU reference, the Embree
// reference and the tests must all see the same points for the same seed on every platform.
class SplitMix64 {
public:
    explicit SplitMix64(std::uint64_t seed) : mState(seed) {}

    std::uint64_t next() {
        std::uint64_t z = (mState += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }

    // Uniform in [0, 1): the top 24 bits are exactly representable as a float, so the result
    // can never round up to 1.
    float nextFloat() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }

private:
    std::uint64_t mState;
};

// Largest divisor of n that is not above sqrt(n), in integers so that perfect squares are exact.
int largestDivisorBelowSqrt(int n) {
    int d = 1;
    while (static_cast<long long>(d + 1) * (d + 1) <= n) ++d;
    for (; d > 1; --d) {
        if (n % d == 0) return d;
    }
    return 1;
}

// Sobol' dimension 2 (primitive polynomial x + 1, direction numbers v_j = the Pascal triangle's
// rows mod 2): the i-th point's 32 binary digits, most significant first.
std::uint32_t sobolSecond(std::uint32_t i) {
    std::uint32_t r = 0;
    for (std::uint32_t v = 1u << 31; i != 0; i >>= 1, v ^= v >> 1)
        if (i & 1u) r ^= v;
    return r;
}

std::uint32_t reverseBits(std::uint32_t x) {
    std::uint32_t r = 0;
    for (int b = 0; b < 32; ++b, x >>= 1) r = (r << 1) | (x & 1u);
    return r;
}

// Owen's nested scrambling of a 32-digit binary fraction: digit d is flipped by a hash of the
// digits above it (and of d and the seed), so points sharing a prefix (an elementary interval)
// are permuted together and the net property survives.
std::uint32_t owenScramble(std::uint32_t x, std::uint64_t seed) {
    std::uint32_t out = 0;
    for (int d = 0; d < 32; ++d) {
        const int bit = 31 - d;
        const std::uint64_t prefix = d == 0 ? 0 : x >> (bit + 1);
        SplitMix64 h(seed ^ (prefix * 0x9E3779B97F4A7C15ull) ^ (static_cast<std::uint64_t>(d) << 56));
        const std::uint32_t flip = static_cast<std::uint32_t>(h.next() >> 63);
        out |= (((x >> bit) & 1u) ^ flip) << bit;
    }
    return out;
}

} // namespace

std::vector<glm::vec2> scrambledNet(int n, std::uint32_t seed) {
    if (n < 1 || n > (1 << 16) || (n & (n - 1)) != 0)
        throw std::invalid_argument("scrambledNet: n must be a power of two up to 65536");
    const std::uint64_t sx = 0xD1B54A32D192ED03ull * (static_cast<std::uint64_t>(seed) + 1);
    const std::uint64_t sy = SplitMix64(sx).next();
    std::vector<glm::vec2> points;
    points.reserve(static_cast<std::size_t>(n));
    // Digits to [-1, 1]: the top 24 bits are exact in a float, and the half-unit keeps the
    // point strictly inside its cell.
    auto coordinate = [](std::uint32_t digits) {
        return -1.0f + 2.0f * ((static_cast<float>(digits >> 8) + 0.5f) * (1.0f / 16777216.0f));
    };
    for (int i = 0; i < n; ++i) {
        const auto u = static_cast<std::uint32_t>(i);
        points.emplace_back(coordinate(owenScramble(reverseBits(u), sx)),
                            coordinate(owenScramble(sobolSecond(u), sy)));
    }
    return points;
}

std::vector<glm::vec2> stratifiedSquare(int n, std::uint32_t seed) {
    if (n < 1) throw std::invalid_argument("stratifiedSquare: n must be >= 1");
    const int nx = largestDivisorBelowSqrt(n);
    const int ny = n / nx;
    // Mix the seed once so that nearby seeds (1, 2, 3...) give unrelated sequences.
    SplitMix64 rng(0xD1B54A32D192ED03ull * (static_cast<std::uint64_t>(seed) + 1));

    std::vector<glm::vec2> points;
    points.reserve(static_cast<std::size_t>(n));
    const float cellW = 2.0f / static_cast<float>(nx);
    const float cellH = 2.0f / static_cast<float>(ny);
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            const float jx = rng.nextFloat();
            const float jy = rng.nextFloat();
            // (i + jx) * cellW can round to exactly 2 for the last cell; keep it inside [-1, 1].
            const float s = glm::min(-1.0f + (static_cast<float>(i) + jx) * cellW, 1.0f);
            const float t = glm::min(-1.0f + (static_cast<float>(j) + jy) * cellH, 1.0f);
            points.emplace_back(s, t);
        }
    }
    return points;
}

} // namespace geometry
