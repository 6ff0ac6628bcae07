// Exact visibility of the data/ scenes made of horizontal rectangles under a horizontal light
// (geometry/reference/Analytic.h), per floor pixel of a render: the ground truth of the GL tests
// that compare a method with the true V rather than with a sampled reference.
#pragma once

#include "RenderTestUtil.h"

#include <geometry/reference/Analytic.h>

#include <cmath>
#include <span>
#include <string>
#include <vector>

namespace testutil {

// The occluders of parallel-square.json, overlap.json and plates-three.json, as the files place
// them (empty for any other scene).
inline std::vector<geometry::HorizontalRect> closedFormRects(const std::string& file) {
    if (file == "parallel-square.json") return {{-0.5f, 0.5f, -0.5f, 0.5f, 1.0f}};
    if (file == "overlap.json")
        return {{-0.9f, 0.1f, -0.4f, 0.6f, 1.0f}, {0.1f, 0.8f, -0.45f, 0.25f, 2.0f}};
    if (file == "plates-three.json")
        return {{-0.8f, -0.1f, 0.0f, 0.7f, 0.6f},
                {0.0f, 0.6f, -0.15f, 0.45f, 1.2f},
                {-0.25f, 0.25f, -0.7f, -0.2f, 1.8f}};
    return {};
}

// Exact V at every floor pixel of `r` (y = 0), NaN elsewhere.
inline std::vector<float> closedFormFloor(const geometry::Scene& scene, const Rendered& r,
                                          std::span<const geometry::HorizontalRect> rects) {
    std::vector<float> v(r.visibility.data.size(), std::nanf(""));
    for (std::size_t i = 0; i < v.size(); ++i) {
        const glm::vec3 p = pixelPosition(r.position, i);
        if (std::isfinite(r.visibility.data[i]) && std::fabs(p.y) < 1e-3f)
            v[i] = geometry::visibilityParallelRects(scene.light, rects, p);
    }
    return v;
}

} // namespace testutil
