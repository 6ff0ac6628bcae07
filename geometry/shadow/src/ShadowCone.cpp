#include <geometry/shadow/ShadowCone.h>

#include <algorithm>
#include <cmath>

namespace geometry {

ShadowCone shadowCone(const Aabb& occluder, const RectLight& light) {
    ShadowCone cone;
    if (occluder.empty()) return cone;
    const glm::vec3 c = 0.5f * (occluder.min + occluder.max);
    const float r = 0.5f * glm::length(occluder.max - occluder.min);
    const float s = std::sqrt(glm::dot(light.u, light.u) + glm::dot(light.v, light.v));
    const glm::vec3 d = c - light.center;
    const float dist = glm::length(d);
    // A relative margin: the spheres' radii grow by it, which only widens the cone.
    const float margin = 1e-4f * (dist + r + s);
    const float sum = r + s + 2.0f * margin;
    if (!(dist > sum) || !std::isfinite(dist)) return cone; // touching spheres: no cone
    cone.whole = false;
    const float rr = r + margin, ss = s + margin;
    cone.apex = (rr * light.center + ss * c) / (rr + ss);
    cone.axis = d / dist;
    cone.sinHalf = sum / dist;
    cone.cosHalf = std::sqrt(std::max(0.0f, 1.0f - cone.sinHalf * cone.sinHalf));
    return cone;
}

bool sphereMayMeetCone(const ShadowCone& cone, const glm::vec3& centre, float radius) {
    if (cone.whole) return true;
    const glm::vec3 d = centre - cone.apex;
    const float len = glm::length(d);
    if (len <= radius) return true;
    // The sphere subtends an angle asin(radius / len) from the apex: it meets the cone when its
    // centre's angle from the axis is at most the half angle plus that.
    const float cosAngle = glm::dot(d, cone.axis) / len;
    const float sinSphere = radius / len;
    const float cosSphere = std::sqrt(std::max(0.0f, 1.0f - sinSphere * sinSphere));
    // Both angles are in [0, pi/2], so their sum is in [0, pi], where cos decreases: the angle
    // to the axis is at most the sum exactly when its cosine is at least cos(sum).
    const float cosLimit = cone.cosHalf * cosSphere - cone.sinHalf * sinSphere;
    return cosAngle >= cosLimit - 1e-6f;
}

} // namespace geometry
