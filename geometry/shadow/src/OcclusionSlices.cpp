// The occlusion-texture frame and lookup (geometry/shadow/OcclusionSlices.h).
#include <geometry/shadow/OcclusionSlices.h>

#include <shared/Horizon.h>

#include <cmath>
#include <limits>

namespace geometry {

int OcclusionFrame::sliceOf(float z) const {
    const float u = (z - zNear) / sliceDepth();
    return std::clamp(static_cast<int>(std::floor(u)), 0, slices - 1);
}

bool OcclusionFrame::covers(const glm::vec3& q) const {
    const float z = depth(q);
    if (!(z > 0.0f)) return false;
    const glm::vec2 st = glm::abs(lateral(q));
    return std::max(st.x, st.y) <= magnification(z) * (1.0f + kOcclusionCoverMargin);
}

glm::vec2 OcclusionFrame::textureCoord(const glm::vec3& q) const {
    return 0.5f + 0.5f * lateral(q) / magnification(depth(q));
}

glm::mat4 OcclusionFrame::sliceProjection() const {
    // Rows: s, t, w / 2, w, each affine in q (glm is column-major: m[column][row]).
    const float d = copDistance;
    const glm::vec4 rs(uStar, -glm::dot(center, uStar));
    const glm::vec4 rt(vStar, -glm::dot(center, vStar));
    const glm::vec4 rw(axis / d, 1.0f - glm::dot(center, axis) / d);
    const glm::vec4 rows[4] = {rs, rt, 0.5f * rw, rw};
    glm::mat4 m(0.0f);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m[c][r] = rows[r][c];
    return m;
}

OcclusionFrame fitOcclusionFrame(const Scene& scene, std::span<const std::size_t> casterObjects,
                                 int slices, const OcclusionFitSettings& settings) {
    return fitOcclusionFrame(scene, scene.light, casterObjects, slices, settings);
}

OcclusionFrame fitOcclusionFrame(const Scene& scene, const RectLight& light,
                                 std::span<const std::size_t> casterObjects, int slices,
                                 const OcclusionFitSettings& settings) {
    OcclusionFrame f;
    f.slices = slices;
    f.center = light.center;
    const glm::vec3 n = light.normal();
    const glm::vec3 a = glm::cross(light.v, n), b = glm::cross(n, light.u);
    f.uStar = a / glm::dot(light.u, a);
    f.vStar = b / glm::dot(light.v, b);

    // The sliced side: where the scene reaches farther from the light's plane.
    float below = 0.0f, above = 0.0f;
    for (const SceneObject& o : scene.objects)
        for (const glm::vec3& q : o.mesh.positions) {
            const float z = glm::dot(q - f.center, n);
            below = std::max(below, z);
            above = std::max(above, -z);
        }
    f.axis = above > below ? -n : n;
    const float zMax = std::max(below, above);
    if (!(zMax > 0.0f)) { // everything in the light's plane: nothing to slice
        f.receiversOutside = true;
        return f;
    }

    // d: the largest keeping every receiver vertex in front of the light inside the frustum
    // (max(|s|, |t|) <= 1 + z / d), within [dMin, dMax].
    const float dMin = zMax / std::max(settings.maxMagnification - 1.0f, 1e-3f);
    const float dMax = 1e3f * zMax;
    const float zTiny = 1e-6f * zMax;
    float d = dMax;
    for (const SceneObject& o : scene.objects)
        for (const glm::vec3& q : o.mesh.positions) {
            const float z = f.depth(q);
            if (z <= zTiny) continue;
            const glm::vec2 st = glm::abs(f.lateral(q));
            const float m = std::max(st.x, st.y);
            if (m > 1.0f) d = std::min(d, z / (m - 1.0f));
        }
    f.copDistance = std::clamp(d, dMin, dMax);
    // Receivers the frustum does not hold (behind or in the light's plane, or beyond the
    // capped frustum): the method shadows them another way (OcclusionFrame::covers).
    for (const SceneObject& o : scene.objects)
        for (const glm::vec3& q : o.mesh.positions)
            f.receiversOutside = f.receiversOutside || !f.covers(q);

    // The casters' depth range inside the frustum: every triangle not wholly outside one of its
    // side planes (s d - z - d <= 0 and the three others) or behind the light, clipped to z >= 0.
    float zNear = std::numeric_limits<float>::max(), zFar = 0.0f;
    for (const std::size_t i : casterObjects) {
        const MeshData& mesh = scene.objects.at(i).mesh;
        for (const glm::uvec3& tri : mesh.triangles) {
            float z[3];
            glm::vec2 st[3];
            for (int k = 0; k < 3; ++k) {
                z[k] = f.depth(mesh.positions[tri[k]]);
                st[k] = f.lateral(mesh.positions[tri[k]]);
            }
            const float zHi = std::max({z[0], z[1], z[2]});
            if (zHi <= 0.0f) continue;
            bool outside = false;
            for (int axis = 0; axis < 2 && !outside; ++axis)
                for (const float sign : {1.0f, -1.0f}) {
                    bool all = true;
                    for (int k = 0; k < 3; ++k)
                        all = all && sign * st[k][axis] * f.copDistance - z[k] - f.copDistance > 0.0f;
                    outside = outside || all;
                }
            if (outside) continue;
            zNear = std::min(zNear, std::max(std::min({z[0], z[1], z[2]}), 0.0f));
            zFar = std::max(zFar, zHi);
        }
    }
    if (zNear > zFar) return f; // no caster in the frustum
    // A single flat caster still gets slabs of some thickness.
    const float minThickness = 1e-3f * zMax;
    if (zFar - zNear < minThickness) zFar = zNear + minThickness;
    f.zNear = zNear;
    f.zFar = zFar;
    f.empty = false;
    return f;
}

SliceLookup sliceLookup(const OcclusionFrame& f, const glm::vec3& p, int k) {
    SliceLookup s;
    const float zP = f.depth(p);
    const float u = (zP - f.zNear) / f.sliceDepth();
    s.weight = std::clamp(u - 1.0f - static_cast<float>(k), 0.0f, 1.0f);
    if (s.weight <= 0.0f) return s;
    const float zk = f.planeDepth(k);
    const float along = zk / zP;         // where the plane cuts the segment P -> light, from P's side
    const float m = 1.0f / f.magnification(zk); // world lateral units -> texture at that plane
    s.center = 0.5f + 0.5f * f.lateral(p) * along * m;
    s.width = (1.0f - along) * m;        // eq. (4): (z_P - z_k) / z_P light sizes
    return s;
}

float horizonFraction(const RectLight& light, const glm::vec3& p, const glm::vec3& n) {
    // The shaders' closed form (shared/Horizon.h): g = a + b s + c t over the light's square.
    return shader::horizonShare(glm::dot(n, light.center - p), glm::dot(n, light.u),
                                glm::dot(n, light.v));
}

} // namespace geometry
