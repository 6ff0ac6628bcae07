// Hard shadow-volume geometry by the two-sided multiplicity rule (geometry/shadow/ShadowVolume.h).
//
// Why the sides are (q, p, p∞), (q, p∞, q∞): for a light-oriented triangle (counter-clockwise
// seen from the light) with directed edge p -> q, the triangle's interior lies to the left of
// p -> q seen from the light. The quad q, p, p∞, q∞ turns clockwise seen from the interior side,
// i.e. counter-clockwise seen from outside, so its normal points away from the triangle's
// interior. Front cap (normal towards the light) and reversed back cap complete a closed,
// outward-oriented semi-infinite frustum per triangle; summing the frusta, the two side quads of
// an edge shared by two consistently oriented triangles cancel, which is exactly m_e = 0.
//
// Runs once per light sample (up to 1024 per reference image), so: two linear passes, scratch
// buffers reused per thread, output written through a pointer after one resize.
#include <geometry/shadow/ShadowVolume.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace geometry {

namespace {

void requireSize(std::size_t actual, std::size_t expected, const char* what) {
    if (actual != expected) {
        throw std::invalid_argument(std::string(what) + ": span has " + std::to_string(actual) +
                                    " entries, topology needs " + std::to_string(expected));
    }
}

} // namespace

void classifyFacing(const Topology& topology, const glm::vec3& light,
                    std::span<std::int8_t> facing) {
    const std::span<const glm::vec3> positions = topology.positions();
    const std::span<const glm::uvec3> triangles = topology.triangles();
    requireSize(facing.size(), triangles.size(), "classifyFacing");
    // Doubles: the float differences are exact in double and the cross product nearly so, which
    // keeps the sign right for lights close to a triangle's plane. Exactly in the plane gives +1
    // (>= 0); the volume is then flat but still closed and consistent.
    const glm::dvec3 l(light);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::uvec3 tri = triangles[t];
        const glm::dvec3 a(positions[tri.x]);
        const glm::dvec3 n =
            glm::cross(glm::dvec3(positions[tri.y]) - a, glm::dvec3(positions[tri.z]) - a);
        facing[t] = glm::dot(n, l - a) >= 0.0 ? std::int8_t{1} : std::int8_t{-1};
    }
}

void edgeMultiplicities(const Topology& topology, std::span<const std::int8_t> facing,
                        std::span<std::int32_t> multiplicity) {
    const std::span<const std::uint32_t> offsets = topology.edgeUseOffsets();
    const std::span<const EdgeUse> uses = topology.edgeUses();
    requireSize(facing.size(), topology.triangles().size(), "edgeMultiplicities (facing)");
    requireSize(multiplicity.size(), topology.edges().size(), "edgeMultiplicities");
    for (std::size_t e = 0; e < multiplicity.size(); ++e) {
        std::int32_t m = 0;
        for (std::uint32_t u = offsets[e]; u < offsets[e + 1]; ++u) {
            m += uses[u].sign * facing[uses[u].triangle];
        }
        multiplicity[e] = m;
    }
}

void appendHardShadowVolume(const Topology& topology, const glm::vec3& light,
                            ShadowVolumeGeometry& out) {
    const std::span<const glm::vec3> positions = topology.positions();
    const std::span<const glm::uvec3> triangles = topology.triangles();
    const std::span<const Edge> edges = topology.edges();

    // Scratch kept per thread: no allocation per call once warmed up.
    thread_local std::vector<std::int8_t> facing;
    thread_local std::vector<std::int32_t> multiplicity;
    facing.resize(triangles.size());
    multiplicity.resize(edges.size());
    classifyFacing(topology, light, facing);
    edgeMultiplicities(topology, facing, multiplicity);

    std::size_t sideQuads = 0, silhouette = 0;
    for (const std::int32_t m : multiplicity) {
        sideQuads += static_cast<std::size_t>(std::abs(m));
        silhouette += m != 0;
    }

    // Layout of the appended block: front caps, back caps, then sides. reserve + push_back
    // rather than resize: resize would first zero-fill megabytes that are overwritten at once.
    const std::size_t capVertices = 3 * triangles.size();
    out.vertices.reserve(out.vertices.size() + 2 * capVertices + 6 * sideQuads);
    std::vector<glm::vec4>& dst = out.vertices;

    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::uvec3 tri = triangles[t];
        // Light-oriented corners: (a, b, c) if facing the light, else (a, c, b). Selects, not
        // branches: facing is close to random per triangle seen from a moving light.
        const bool flip = facing[t] < 0;
        dst.emplace_back(positions[tri.x], 1.0f);
        dst.emplace_back(positions[flip ? tri.z : tri.y], 1.0f);
        dst.emplace_back(positions[flip ? tri.y : tri.z], 1.0f);
    }
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::uvec3 tri = triangles[t];
        const bool flip = facing[t] < 0;
        // Reversed at infinity: seen from outside (beyond it) it is counter-clockwise.
        dst.emplace_back(positions[tri.x] - light, 0.0f);
        dst.emplace_back(positions[flip ? tri.y : tri.z] - light, 0.0f);
        dst.emplace_back(positions[flip ? tri.z : tri.y] - light, 0.0f);
    }

    for (std::size_t e = 0; e < edges.size(); ++e) {
        const std::int32_t m = multiplicity[e];
        if (m == 0) continue;
        // m > 0: the light-oriented triangles' surplus runs v0 -> v1, so p -> q = v0 -> v1.
        const glm::vec3 p = positions[m > 0 ? edges[e].v0 : edges[e].v1];
        const glm::vec3 q = positions[m > 0 ? edges[e].v1 : edges[e].v0];
        const glm::vec4 pf(p, 1.0f), qf(q, 1.0f);
        const glm::vec4 pi(p - light, 0.0f), qi(q - light, 0.0f);
        for (std::int32_t copy = std::abs(m); copy > 0; --copy) {
            dst.push_back(qf);
            dst.push_back(pf);
            dst.push_back(pi);
            dst.push_back(qf);
            dst.push_back(pi);
            dst.push_back(qi);
        }
    }

    out.capTriangles += 2 * triangles.size();
    out.sideTriangles += 2 * sideQuads;
    out.silhouetteEdges += silhouette;
}

} // namespace geometry
