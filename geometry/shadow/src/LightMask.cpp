// Light-sample masks (geometry/shadow/LightMask.h): the pattern and the per-pixel shift (the
// shaders' own shaders/shared/LightMask.h).
#include <geometry/shadow/LightMask.h>

#include <shared/LightMask.h>
#include <shared/Parts.h>

#include <geometry/core/Error.h>
#include <geometry/core/Sampling.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace geometry {


std::vector<glm::vec2> lightMaskPattern(int n, std::uint32_t seed) {
    if (std::find(std::begin(kLightMaskSampleCounts), std::end(kLightMaskSampleCounts), n) ==
        std::end(kLightMaskSampleCounts))
        throw InputError("light-mask samples must be 32, 64, 128 or 256 (got " +
                         std::to_string(n) + ")");
    std::vector<glm::vec2> points = stratifiedSquare(n, seed);
    // By angle about the centre, so that the samples between two rays from the centre are a
    // run of consecutive indices (shaders/shared/LightMask.h's fixed-pattern path).
    std::stable_sort(points.begin(), points.end(), [](glm::vec2 a, glm::vec2 b) {
        return std::atan2(a.y, a.x) < std::atan2(b.y, b.x);
    });
    return points;
}

std::vector<int> lightMaskRunQuadrants(std::span<const glm::vec2> pattern) {
    if (pattern.size() % 8 != 0)
        throw std::logic_error("light-mask pattern: " + std::to_string(pattern.size()) +
                               " samples are not whole runs of 8");
    std::vector<int> quadrants;
    for (std::size_t run = 0; run < pattern.size(); run += 8) {
        const int q = shader::partsQuadrantOf(pattern[run]);
        for (std::size_t i = run + 1; i < run + 8; ++i)
            if (shader::partsQuadrantOf(pattern[i]) != q)
                throw std::logic_error("light-mask pattern: samples " + std::to_string(run) +
                                       ".." + std::to_string(run + 7) +
                                       " lie in more than one quadrant of the light");
        quadrants.push_back(q);
    }
    return quadrants;
}

float maskSampleAngle(glm::vec2 y) {
    return std::atan2(y.y, y.x);
}

glm::vec2 maskPixelShift(int x, int y) {
    return shader::maskPixelShift(glm::ivec2(x, y));
}

glm::vec2 maskShifted(glm::vec2 y, glm::vec2 shift) {
    return shader::maskShifted(y, shift);
}

} // namespace geometry
