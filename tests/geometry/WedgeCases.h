// Random lights and edges for the penumbra-wedge tests (WedgeTest) and benchmarks
// (geometry_bench's wedge cases): one generator, so the benchmarks time the very edges the tests
// were written against (same seed, same draws).
#pragma once

#include "TestRandom.h"

#include <geometry/core/Types.h>

#include <glm/glm.hpp>

#include <cmath>
#include <utility>

namespace wedgecases {

using geometry::RectLight;
using glm::dvec3;
using glm::vec3;
using testutil::Rng;

// A random light: any orientation, sizes over two decades, and often a parallelogram.
inline RectLight randomLight(Rng& rng) {
    RectLight light;
    light.center = vec3(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5));
    const dvec3 a = rng.direction();
    dvec3 b = glm::normalize(glm::cross(a, rng.direction()));
    if (rng.uniform(0, 1) < 0.5) b = glm::normalize(b + rng.uniform(-0.8, 0.8) * a); // skewed
    light.u = vec3(a * rng.uniform(0.05, 2.0));
    light.v = vec3(b * rng.uniform(0.05, 2.0));
    return light;
}

struct Frame {
    dvec3 c, u, v, n;
};
inline Frame frameOf(const RectLight& l) {
    const dvec3 u(l.u), v(l.v);
    return {dvec3(l.center), u, v, glm::normalize(glm::cross(u, v))};
}
// A point in light coordinates: s, t along u, v, h along the unit normal.
inline vec3 lightPoint(const Frame& f, double s, double t, double h) {
    return vec3(f.c + s * f.u + t * f.v + h * f.n);
}

enum class EdgeKind {
    Generic,
    TowardLight,    // nearly parallel to the light direction, one end much closer
    CrossesPlane,   // crosses the light's plane outside the light
    Short,          // length ~1e-4 of the scene
    CloseToLight,   // occluder just below the light, over it
    NearlyInPlane,  // within 1e-5 of the light's plane, outside the light
    TowardCorner,   // the edge's line passes through a light corner
    ParallelToSide, // parallel to u
    Touching,       // reaches into the light: unbounded
    Count
};

struct TestEdge {
    vec3 e0, e1;
    EdgeKind kind;
};

inline TestEdge randomEdge(Rng& rng, const RectLight& light, EdgeKind kind) {
    const Frame f = frameOf(light);
    const double side = rng.uniform(0, 1) < 0.5 ? -1.0 : 1.0;
    const double size = glm::length(f.u) + glm::length(f.v);
    auto below = [&](double hMin, double hMax) {
        return lightPoint(f, rng.uniform(-4, 4), rng.uniform(-4, 4),
                          side * rng.uniform(hMin, hMax) * size);
    };
    switch (kind) {
    case EdgeKind::Generic:
        return {below(0.05, 5), below(0.05, 5), kind};
    case EdgeKind::TowardLight: {
        const vec3 e0 = below(2, 6);
        const dvec3 towards = f.c + rng.uniform(-1, 1) * f.u + rng.uniform(-1, 1) * f.v;
        const dvec3 dir = glm::normalize(towards - dvec3(e0)) + 1e-3 * rng.direction();
        return {e0,
                vec3(dvec3(e0) + rng.uniform(0.5, 0.99) * glm::length(towards - dvec3(e0)) *
                                     glm::normalize(dir)),
                kind};
    }
    case EdgeKind::CrossesPlane: {
        // Crossing point outside the light (|s| or |t| > 1), ends on both sides.
        double s = rng.uniform(1.05, 4), t = rng.uniform(-4, 4);
        if (rng.uniform(0, 1) < 0.5) std::swap(s, t);
        if (rng.uniform(0, 1) < 0.5) s = -s;
        const dvec3 x = f.c + s * f.u + t * f.v;
        const dvec3 dir = rng.direction();
        if (std::abs(glm::dot(dir, f.n)) < 0.05) return {below(0.1, 3), below(0.1, 3), kind};
        const double a = rng.uniform(0.01, 2) * size, b = rng.uniform(0.01, 2) * size;
        return {vec3(x - a * dir), vec3(x + b * dir), kind};
    }
    case EdgeKind::Short: {
        const vec3 e0 = below(0.05, 5);
        return {e0, vec3(dvec3(e0) + 1e-4 * size * rng.direction()), kind};
    }
    case EdgeKind::CloseToLight:
        return {lightPoint(f, rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5),
                           side * rng.uniform(1e-4, 1e-2) * size),
                lightPoint(f, rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5),
                           side * rng.uniform(1e-4, 1e-2) * size),
                kind};
    case EdgeKind::NearlyInPlane: {
        const double s = rng.uniform(1.2, 3);
        return {lightPoint(f, s, rng.uniform(-3, 3), side * 1e-5 * size),
                lightPoint(f, s + rng.uniform(0.1, 2), rng.uniform(-3, 3),
                           side * rng.uniform(-1e-5, 1e-5) * size),
                kind};
    }
    case EdgeKind::TowardCorner: {
        const dvec3 corner = f.c + (rng.uniform(0, 1) < 0.5 ? 1.0 : -1.0) * f.u +
                             (rng.uniform(0, 1) < 0.5 ? 1.0 : -1.0) * f.v;
        const dvec3 e0 = dvec3(below(0.5, 4));
        return {vec3(e0), vec3(corner + rng.uniform(0.1, 0.9) * (e0 - corner)), kind};
    }
    case EdgeKind::ParallelToSide: {
        const vec3 e0 = below(0.05, 4);
        return {e0, vec3(dvec3(e0) + rng.uniform(-3, 3) * f.u), kind};
    }
    case EdgeKind::Touching: {
        const dvec3 y = f.c + rng.uniform(-1, 1) * f.u + rng.uniform(-1, 1) * f.v;
        const dvec3 dir = rng.direction() * size;
        const double a = rng.uniform(0, 1) < 0.3 ? 0.0 : rng.uniform(0.01, 2);
        return {vec3(y - a * dir), vec3(y + rng.uniform(0.01, 2) * dir), kind};
    }
    default:
        break;
    }
    return {below(0.05, 5), below(0.05, 5), EdgeKind::Generic};
}

} // namespace wedgecases
