// Seeded random numbers for the randomised tests (one engine per test, so each test's draws are
// reproducible on their own).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <random>

namespace testutil {

struct Rng {
    std::mt19937_64 engine;
    explicit Rng(std::uint64_t seed) : engine(seed) {}
    double uniform(double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(engine);
    }
    // A unit direction, uniform on the sphere (rejection from the unit ball, away from 0).
    glm::dvec3 direction() {
        for (;;) {
            const glm::dvec3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
            const double l = glm::length(v);
            if (l > 0.1 && l <= 1.0) return v / l;
        }
    }
    // A point uniform in the unit ball.
    glm::dvec3 inBall() {
        for (;;) {
            const glm::dvec3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
            if (glm::dot(v, v) <= 1.0) return v;
        }
    }
};

// A unit direction from three standard normal draws of `rng` (redrawn while shorter than 1e-3).
inline glm::dvec3 gaussianDirection(std::mt19937& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    for (;;) {
        const glm::dvec3 d(n(rng), n(rng), n(rng));
        if (glm::length(d) > 1e-3) return glm::normalize(d);
    }
}

} // namespace testutil
