// shaders/shared/WedgeHull.h and shaders/shared/Coverage.h on the driver:
// - a vertex-pulling vertex shader and a fragment shader that include them compile and link;
// - drawn by vertex pulling (back faces only, no depth test, depth clamp), the hull covers every
//   pixel whose view ray meets it exactly once, from outside it and from inside it;
// - a compute shader runs them over random edges, lights and points, and the results match the same
//   source compiled as C++ (geometry/shadow/WedgeHull.h, geometry/shadow/Coverage.h): same kinds, same hulls and
//   coverage up to the driver's rounding, the same vertex table, and GPU hulls that contain every
//   shadow ray through their edge.
#include "TestRandom.h"

#include "GlTestEnv.h"
#include "ScratchDir.h"

#include <geometry/shadow/Coverage.h>
#include <geometry/shadow/Wedge.h>
#include <geometry/shadow/WedgeHull.h>
#include <gpu/gl/Objects.h>
#include <gpu/gl/ShaderLoader.h>
#include <gpu/gl/State.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

using glm::dvec3;
using glm::vec3;
using glm::vec4;

// How a renderer would use the libraries: one draw of 24 vertices per edge, the edges pulled
// from a buffer, the planes passed flat to the fragment shader.
const char* kPullVert = R"(#include "shared/WedgeHull.h"
layout(std430, binding = 0) readonly buffer Edges { vec4 edges[]; }; // e0, e1 per edge
uniform mat4 viewProj;
uniform vec3 lightC;
uniform vec3 lightU;
uniform vec3 lightV;
flat out vec4 vPlanes[4];
flat out vec3 vE0;
flat out vec3 vE1;
void main() {
    int edge = gl_VertexID / kWedgeHullVertexCount;
    vE0 = edges[2 * edge].xyz;
    vE1 = edges[2 * edge + 1].xyz;
    WedgeHull hull = wedgeHull(vE0, vE1, lightC, lightU, lightV);
    gl_Position = wedgeHullClipVertex(hull, gl_VertexID % kWedgeHullVertexCount, viewProj);
    vPlanes = hull.planes;
}
)";

const char* kCoverageFrag = R"(#include "shared/WedgeHull.h"
#include "shared/Coverage.h"
uniform vec3 lightC;
uniform vec3 lightU;
uniform vec3 lightV;
uniform vec3 receiver;
flat in vec4 vPlanes[4];
flat in vec3 vE0;
flat in vec3 vE1;
out vec4 colour;
void main() {
    if (!wedgeHullContains(vPlanes, receiver)) discard;
    colour = vec4(edgeCoverage(receiver, vE0, vE1, coverageLight(lightC, lightU, lightV)));
}
)";

// vec4s per item: (kind, coverage, contains, 0), g[4], planes[4], the 24 vertices.
constexpr int kStride = 33;

const char* kCheckComp = R"(#include "shared/WedgeHull.h"
#include "shared/Coverage.h"
layout(local_size_x = 64) in;
struct CheckInput {
    vec4 e0;
    vec4 e1;
    vec4 c;
    vec4 u;
    vec4 v;
    vec4 p;
};
layout(std430, binding = 0) readonly buffer Inputs { CheckInput inputs[]; };
layout(std430, binding = 1) writeonly buffer Outputs { vec4 outputs[]; };
uniform uint count;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    CheckInput x = inputs[i];
    WedgeHull hull = wedgeHull(x.e0.xyz, x.e1.xyz, x.c.xyz, x.u.xyz, x.v.xyz);
    CoverageLight light = coverageLight(x.c.xyz, x.u.xyz, x.v.xyz);
    uint base = i * 33u;
    outputs[base] = vec4(float(hull.kind), edgeCoverage(x.p.xyz, x.e0.xyz, x.e1.xyz, light),
                         wedgeHullContains(hull.planes, x.p.xyz) ? 1.0 : 0.0, 0.0);
    for (int k = 0; k < 4; ++k) {
        outputs[base + 1u + uint(k)] = vec4(hull.g[k], 0.0);
        outputs[base + 5u + uint(k)] = hull.planes[k];
    }
    for (int k = 0; k < kWedgeHullVertexCount; ++k)
        outputs[base + 9u + uint(k)] = wedgeHullVertex(hull, k);
}
)";

struct CheckInput {
    vec4 e0, e1, c, u, v, p;
};
static_assert(sizeof(CheckInput) == 6 * 16, "CheckInput must match std430");

using testutil::Rng;

// Runs a compute program of one invocation per item (the items at binding 0, their number in the
// uniform `count`, `perItem` vec4 outputs each at binding 1) and returns the outputs.
template <typename Input>
std::vector<vec4> runItems(const gpu::Program& program, const std::vector<Input>& inputs,
                           std::size_t perItem, const char* label) {
    gpu::Buffer in({.size = inputs.size() * sizeof(Input), .data = inputs.data(), .label = label});
    gpu::Buffer out({.size = inputs.size() * perItem * sizeof(vec4), .label = label});
    glUseProgram(program.id());
    glProgramUniform1ui(program.id(), program.uniformLocation("count"),
                        static_cast<GLuint>(inputs.size()));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
    glDispatchCompute(static_cast<GLuint>((inputs.size() + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<vec4> result(inputs.size() * perItem);
    glGetNamedBufferSubData(out.id(), 0, static_cast<GLsizeiptr>(result.size() * sizeof(vec4)),
                            result.data());
    glUseProgram(0);
    return result;
}

// Random light and edge (every fifth edge reaches into the light: Fullscreen), a point on a
// shadow ray through the edge (so the coverage is mostly non-zero), and the ray's parameters.
struct Item {
    CheckInput in;
    double lambda, s, t; // the ray through e0 + lambda (e1 - e0) from light point (s, t)
};

Item randomItem(Rng& rng, int n) {
    Item it;
    const dvec3 c(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5));
    const dvec3 a = rng.direction();
    const dvec3 b = glm::normalize(glm::cross(a, rng.direction()));
    const dvec3 u = a * rng.uniform(0.05, 2.0), v = b * rng.uniform(0.05, 2.0);
    const dvec3 nrm = glm::normalize(glm::cross(u, v));
    const double side = rng.uniform(0, 1) < 0.5 ? -1.0 : 1.0;
    const double size = glm::length(u) + glm::length(v);
    auto below = [&] {
        return c + rng.uniform(-4, 4) * u + rng.uniform(-4, 4) * v +
               side * rng.uniform(0.05, 5) * size * nrm;
    };
    dvec3 e0 = below(), e1 = below();
    if (n % 5 == 4) { // through the light
        const dvec3 y = c + rng.uniform(-1, 1) * u + rng.uniform(-1, 1) * v;
        e0 = y - rng.uniform(0.1, 2) * size * nrm;
        e1 = y + rng.uniform(0.1, 2) * size * nrm;
    }
    it.lambda = rng.uniform(0, 1);
    it.s = rng.uniform(-1, 1);
    it.t = rng.uniform(-1, 1);
    const dvec3 x = e0 + it.lambda * (e1 - e0);
    const dvec3 p = x + std::pow(10.0, rng.uniform(-2, 2)) * (x - (c + it.s * u + it.t * v));
    it.in = {vec4(vec3(e0), 1), vec4(vec3(e1), 1), vec4(vec3(c), 1),
             vec4(vec3(u), 0),  vec4(vec3(v), 0),  vec4(vec3(p), 1)};
    return it;
}

// Largest signed plane value of p over four planes, in double (> 0: outside).
double planeExcess(const vec4* planes, const dvec3& p) {
    double m = -1e300;
    for (int i = 0; i < 4; ++i)
        m = std::max(m, glm::dot(dvec3(vec3(planes[i])), p) + double(planes[i].w));
    return m;
}

class WedgeHullShaderTest : public GlTest {};

TEST_F(WedgeHullShaderTest, VertexPullingAndCoverageShadersCompileAndLink) {
    testutil::ScratchDir dir;
    gpu::ShaderLoader loader(gpu::defaultShaderDir());
    gpu::Program program =
        loader.load({.stages = {{GL_VERTEX_SHADER, dir.write("pull.vert", kPullVert)},
                                {GL_FRAGMENT_SHADER, dir.write("coverage.frag", kCoverageFrag)}},
                     .label = "wedge-hull-pull"});
    ASSERT_TRUE(program);
    EXPECT_GE(program.uniformLocation("viewProj"), 0);
    EXPECT_GE(program.uniformLocation("receiver"), 0);
}

TEST_F(WedgeHullShaderTest, ComputeMatchesTheCppBuild) {
    testutil::ScratchDir dir;
    gpu::ShaderLoader loader(gpu::defaultShaderDir());
    gpu::Program program =
        loader.load({.stages = {{GL_COMPUTE_SHADER, dir.write("check.comp", kCheckComp)}},
                     .label = "wedge-hull-check"});
    ASSERT_TRUE(program);

    Rng rng(1234);
    constexpr int kItems = 4000;
    std::vector<Item> items;
    std::vector<CheckInput> inputs;
    for (int n = 0; n < kItems; ++n) {
        items.push_back(randomItem(rng, n));
        inputs.push_back(items.back().in);
    }
    // Two degenerate edges: zero length.
    inputs[0].e1 = inputs[0].e0;
    inputs[1].e0 = inputs[1].e1;
    const std::vector<vec4> gpu = runItems(program, inputs, kStride, "hull-check");
    ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));

    int kindMismatch = 0, bounded = 0, fullscreen = 0, degenerate = 0, hullDiffers = 0;
    int coverageDiffers = 0, rayPointsChecked = 0;
    double maxPlaneDiff = 0.0, maxCoverageDiff = 0.0;
    for (int n = 0; n < kItems; ++n) {
        const CheckInput& x = inputs[n];
        const vec4* g = gpu.data() + static_cast<std::size_t>(n) * kStride;
        const int kind = static_cast<int>(g[0].x);
        const geometry::WedgeHull cpu =
            geometry::wedgeHull(vec3(x.e0), vec3(x.e1), vec3(x.c), vec3(x.u), vec3(x.v));
        kindMismatch += kind != cpu.kind;
        bounded += kind == geometry::kWedgeHullBounded;
        fullscreen += kind == geometry::kWedgeHullFullscreen;
        degenerate += kind == geometry::kWedgeHullDegenerate;
        if (n < 2) {
            EXPECT_EQ(kind, geometry::kWedgeHullDegenerate);
        }

        // The GLSL vertex table is the C++ one: the GPU's 24 vertices rebuilt from its own hull.
        geometry::WedgeHull fromGpu = geometry::wedgeHullEmpty(vec3(x.e0), vec3(x.e1));
        fromGpu.kind = kind;
        for (int k = 0; k < 4; ++k) {
            fromGpu.g[k] = vec3(g[1 + k]);
            fromGpu.planes[k] = g[5 + k];
        }
        for (int k = 0; k < geometry::kWedgeHullVertexCount; ++k)
            ASSERT_EQ(g[9 + k], geometry::wedgeHullVertex(fromGpu, k)) << "item " << n;

        // Coverage: the driver's rounding (fused multiply-adds, its own division and square
        // root) against the C++ twin, measured in the light's area; apart from a side flip at
        // the hard-shadow plane.
        const geometry::CoverageLight light =
            geometry::coverageLight(vec3(x.c), vec3(x.u), vec3(x.v));
        const float cov = geometry::edgeCoverage(vec3(x.p), vec3(x.e0), vec3(x.e1), light);
        const double covDiff = std::abs(double(g[0].y) - double(cov));
        if (covDiff > 0.5) {
            ++coverageDiffers;
        } else {
            maxCoverageDiff = std::max(maxCoverageDiff, covDiff);
        }

        if (kind != geometry::kWedgeHullBounded) continue;
        // Same planes as the twin, unless the driver's asin picked another side facet (then the
        // planes differ outright; either choice is conservative, which is checked below).
        double planeDiff = 0.0;
        for (int k = 0; k < 4; ++k) {
            const vec4 d = glm::abs(g[5 + k] - cpu.planes[k]);
            planeDiff = std::max({planeDiff, double(d.x), double(d.y), double(d.z),
                                  double(d.w) / (1.0 + glm::length(vec3(x.e0)))});
        }
        if (planeDiff > 1e-4) {
            ++hullDiffers;
        } else {
            maxPlaneDiff = std::max(maxPlaneDiff, planeDiff);
        }
        // The GPU's planes contain the shadow rays through the edge (a + t (a - y)).
        const dvec3 e0(vec3(x.e0)), e1(vec3(x.e1)), c(vec3(x.c)), u(vec3(x.u)), v(vec3(x.v));
        for (double lambda : {0.0, 1.0, items[n].lambda}) {
            for (int corner = 0; corner < 5; ++corner) {
                const double s = corner < 4 ? (corner & 1 ? 1.0 : -1.0) : items[n].s;
                const double t = corner < 4 ? (corner & 2 ? 1.0 : -1.0) : items[n].t;
                const dvec3 a = e0 + lambda * (e1 - e0);
                for (double tt : {0.0, 1e-3, 1.0, 1e3}) {
                    ASSERT_LE(planeExcess(g + 5, a + tt * (a - (c + s * u + t * v))), 0.0)
                        << "item " << n << " lambda " << lambda << " t " << tt;
                    ++rayPointsChecked;
                }
            }
        }
        // The sample point is on such a ray: inside by the GPU's own plane test too.
        EXPECT_EQ(g[0].z, 1.0f) << "item " << n;
    }
    std::printf("[ glsl     ] %d items: %d bounded, %d fullscreen, %d degenerate; %d kinds differ "
                "from the C++ twin\n",
                kItems, bounded, fullscreen, degenerate, kindMismatch);
    std::printf("[ glsl     ] planes: max difference %.2g (%d hulls with another side facet); "
                "coverage: max difference %.2g (%d side flips); %d ray points inside\n",
                maxPlaneDiff, hullDiffers, maxCoverageDiff, coverageDiffers, rayPointsChecked);
    // Kinds decided on thresholds may flip only where a value sits on one within rounding.
    EXPECT_LE(kindMismatch, kItems / 1000);
    EXPECT_GT(bounded, kItems / 2);
    EXPECT_GT(fullscreen, kItems / 10);
    EXPECT_LE(hullDiffers, kItems / 100);
    // Rounding differences of a few ulps in the inputs of the projection and the clip: far below
    // the float-vs-double tolerance of the geometry test (1e-3).
    EXPECT_LE(maxCoverageDiff, 1e-4);
    EXPECT_LE(coverageDiffers, kItems / 1000);
    EXPECT_LE(maxPlaneDiff, 1e-5);
}

const char* kCountFrag = R"(out float count;
void main() { count = 1.0; }
)";

// Back faces of the hull drawn with additive blending count, per pixel, the faces its view ray
// leaves the hull through: exactly 1 where the ray (from the eye through the pixel centre) meets
// the hull, 0 elsewhere; decided on the CPU with the twin's planes (the hull is the intersection
// of its four half-spaces) for the centre and the four corners of each pixel, and pixels whose
// rays disagree (on the hull's outline) left out. Eyes outside the hull and inside it.
// wedgeHullNarrowed (wedges-bitmask silhouettes=potential) on the driver against the C++ build:
// the same kinds and planes for random edges, lights and two third vertices.
const char* kNarrowedComp = R"(#include "shared/WedgeHull.h"
layout(local_size_x = 64) in;
struct NarrowInput {
    vec4 e0;
    vec4 e1;
    vec4 c;
    vec4 u;
    vec4 v;
    vec4 w0;
    vec4 w1;
};
layout(std430, binding = 0) readonly buffer Inputs { NarrowInput inputs[]; };
layout(std430, binding = 1) writeonly buffer Outputs { vec4 outputs[]; };
uniform uint count;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    NarrowInput x = inputs[i];
    WedgeHull hull = wedgeHullNarrowed(x.e0.xyz, x.e1.xyz, x.c.xyz, x.u.xyz, x.v.xyz, true,
                                       x.w0.xyz, x.w1.xyz);
    outputs[5u * i] = vec4(float(hull.kind), 0.0, 0.0, 0.0);
    for (int k = 0; k < 4; ++k) outputs[5u * i + 1u + uint(k)] = hull.planes[k];
}
)";

TEST_F(WedgeHullShaderTest, NarrowedComputeMatchesTheCppBuild) {
    testutil::ScratchDir dir;
    gpu::ShaderLoader loader(gpu::defaultShaderDir());
    gpu::Program program =
        loader.load({.stages = {{GL_COMPUTE_SHADER, dir.write("narrow.comp", kNarrowedComp)}},
                     .label = "wedge-hull-narrow-check"});
    ASSERT_TRUE(program);
    Rng rng(99);
    constexpr int kItems = 4000;
    struct NarrowInput {
        vec4 e0, e1, c, u, v, w0, w1;
    };
    std::vector<NarrowInput> inputs;
    for (int n = 0; n < kItems; ++n) {
        const Item it = randomItem(rng, n);
        const vec3 e0 = vec3(it.in.e0), e1 = vec3(it.in.e1);
        const float len = glm::length(e1 - e0) + 0.1f;
        const vec3 w0 = e0 + len * vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        const vec3 w1 = e0 + len * vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        inputs.push_back({it.in.e0, it.in.e1, it.in.c, it.in.u, it.in.v, vec4(w0, 1.0f),
                          vec4(w1, 1.0f)});
    }
    // And a quarter as many edges just under the light's plane, across the light, as a box's
    // top edges under a lamp (one third vertex across the top, one down the side): the whole
    // wedge over 178 degrees, Fullscreen, the narrowed one often bounded (wide sectors).
    for (int n = 0; n < kItems / 4; ++n) {
        const vec3 c(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3));
        const vec3 u(rng.uniform(0.1, 1), 0.0f, 0.0f), v(0.0f, 0.0f, rng.uniform(0.1, 1));
        const float depth = -std::pow(10.0f, float(rng.uniform(-4, -1.5))) * (u.x + v.z);
        const vec3 e0 = c + vec3(-rng.uniform(0.2, 2) * u.x, depth, rng.uniform(-0.8, 0.8) * v.z);
        const vec3 e1 = c + vec3(rng.uniform(0.2, 2) * u.x, depth, e0.z - c.z + rng.uniform(-0.1, 0.1) * v.z);
        const float len = glm::length(e1 - e0);
        const vec3 across = glm::normalize(glm::cross(vec3(0.0f, 1.0f, 0.0f), e1 - e0));
        const vec3 w0 = e0 + len * (rng.uniform(0, 1) < 0.5 ? 1.0f : -1.0f) * across;
        const vec3 w1 = e0 - len * vec3(0.0f, 1.0f, 0.0f);
        inputs.push_back({vec4(e0, 1.0f), vec4(e1, 1.0f), vec4(c, 1.0f), vec4(u, 0.0f),
                          vec4(v, 0.0f), vec4(w0, 1.0f), vec4(w1, 1.0f)});
    }
    const int items = static_cast<int>(inputs.size());
    const std::vector<vec4> gpu = runItems(program, inputs, 5, "hull-narrow");
    int kindMismatch = 0, planeMismatch = 0, sideMismatch = 0, narrowed = 0, bounded = 0,
        degenerate = 0, wide = 0;
    for (int n = 0; n < items; ++n) {
        const NarrowInput& x = inputs[n];
        const geometry::WedgeHull cpu = geometry::wedgeHullNarrowed(
            vec3(x.e0), vec3(x.e1), vec3(x.c), vec3(x.u), vec3(x.v), true, vec3(x.w0),
            vec3(x.w1));
        const geometry::WedgeHull whole =
            geometry::wedgeHull(vec3(x.e0), vec3(x.e1), vec3(x.c), vec3(x.u), vec3(x.v));
        const int kind = static_cast<int>(gpu[5 * n].x);
        kindMismatch += kind != cpu.kind;
        bounded += cpu.kind == geometry::kWedgeHullBounded;
        degenerate += cpu.kind == geometry::kWedgeHullDegenerate;
        wide += cpu.kind == geometry::kWedgeHullBounded &&
                whole.kind == geometry::kWedgeHullFullscreen;
        if (kind != cpu.kind || cpu.kind != geometry::kWedgeHullBounded) continue;
        // Front and back (0, 1): what the narrowing turns. The side planes (2, 3) are the whole
        // hull's, whose choice among near-equal candidates the driver may make otherwise
        // (counted apart: WedgeHullShaderTest.ComputeMatchesTheCppBuild's finding).
        bool differs = false, sideDiffers = false, tighter = false;
        for (int k = 0; k < 4; ++k) {
            const vec4 g = gpu[5 * n + 1 + k];
            const bool d = glm::length(vec3(g) - vec3(cpu.planes[k])) > 1e-4f;
            (k < 2 ? differs : sideDiffers) = (k < 2 ? differs : sideDiffers) || d;
            tighter = tighter || glm::length(vec3(whole.planes[k]) - vec3(cpu.planes[k])) > 1e-4f;
        }
        planeMismatch += differs;
        sideMismatch += sideDiffers;
        narrowed += tighter;
    }
    std::printf("  %d items: %d bounded (%d narrowed, %d of a Fullscreen wedge), %d with no "
                "silhouette receiver; %d kinds, %d front or back planes and %d side planes differ "
                "from the C++ build\n",
                items, bounded, narrowed, wide, degenerate, kindMismatch, planeMismatch,
                sideMismatch);
    EXPECT_GT(narrowed, kItems / 10);
    EXPECT_GT(wide, kItems / 16);
    EXPECT_EQ(kindMismatch, 0);
    EXPECT_EQ(planeMismatch, 0);
}

// wedgeHullSilhouetteCone and wedgeHullTruncateCone (the two cones that replace a Fullscreen
// potential edge's hull) on the driver against the C++ build: edges whose line passes through the
// light, both halves, cut to a box around the edge.
const char* kConeComp = R"(#include "shared/WedgeHull.h"
layout(local_size_x = 64) in;
struct ConeInput {
    vec4 e0;
    vec4 e1;
    vec4 c;
    vec4 u;
    vec4 v;
    vec4 w0;
    vec4 w1;
    vec4 lo;
    vec4 hi;
};
layout(std430, binding = 0) readonly buffer Inputs { ConeInput inputs[]; };
layout(std430, binding = 1) writeonly buffer Outputs { vec4 outputs[]; };
uniform uint count;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    ConeInput x = inputs[i];
    for (int which = 0; which < 2; ++which) {
        WedgeHull hull = wedgeHullTruncateCone(
            wedgeHullSilhouetteCone(x.e0.xyz, x.e1.xyz, x.c.xyz, x.u.xyz, x.v.xyz, x.w0.xyz,
                                    x.w1.xyz, which),
            x.c.xyz, x.u.xyz, x.v.xyz, x.lo.xyz, x.hi.xyz);
        uint base = 6u * (2u * i + uint(which));
        outputs[base] = vec4(float(hull.kind), hull.reach, float(hull.cone), 0.0);
        outputs[base + 1u] = vec4(hull.apex, 0.0);
        for (int k = 0; k < 4; ++k) outputs[base + 2u + uint(k)] = hull.planes[k];
    }
}
)";

TEST_F(WedgeHullShaderTest, SilhouetteConesMatchTheCppBuild) {
    testutil::ScratchDir dir;
    gpu::ShaderLoader loader(gpu::defaultShaderDir());
    gpu::Program program =
        loader.load({.stages = {{GL_COMPUTE_SHADER, dir.write("cone.comp", kConeComp)}},
                     .label = "wedge-hull-cone-check"});
    ASSERT_TRUE(program);
    Rng rng(4242);
    constexpr int kItems = 4000;
    struct ConeInput {
        vec4 e0, e1, c, u, v, w0, w1, lo, hi;
    };
    std::vector<ConeInput> inputs;
    for (int n = 0; n < kItems; ++n) {
        // One draw per statement: the same cases whatever the compiler's argument order.
        dvec3 c;
        for (int k = 0; k < 3; ++k) c[k] = rng.uniform(-5, 5);
        const dvec3 a = rng.direction();
        const dvec3 b = glm::normalize(glm::cross(a, rng.direction()));
        const double su = rng.uniform(0.05, 2.0);
        const double sv = rng.uniform(0.05, 2.0);
        const dvec3 u = a * su, v = b * sv;
        const double size = glm::length(u) + glm::length(v);
        const double ys = rng.uniform(-0.9, 0.9);
        const double yt = rng.uniform(-0.9, 0.9);
        const dvec3 y = c + ys * u + yt * v;
        dvec3 d = rng.direction();
        const dvec3 nrm = glm::normalize(glm::cross(u, v));
        if (std::abs(glm::dot(d, nrm)) < 0.05) d = glm::normalize(d + 0.2 * nrm);
        const double d0 = rng.uniform(0.05, 3) * size;
        const double d1 = d0 + rng.uniform(0.01, 2) * size;
        dvec3 e0 = y + d0 * d, e1 = y + d1 * d;
        if (n % 2 == 0) std::swap(e0, e1);
        const double len = glm::length(e1 - e0);
        const dvec3 w0 = e0 + len * rng.direction();
        const dvec3 w1 = e0 + len * rng.direction();
        const dvec3 lo = glm::min(e0, e1) - 5.0 * size, hi = glm::max(e0, e1) + 5.0 * size;
        inputs.push_back({vec4(vec3(e0), 1), vec4(vec3(e1), 1), vec4(vec3(c), 1),
                          vec4(vec3(u), 0), vec4(vec3(v), 0), vec4(vec3(w0), 1),
                          vec4(vec3(w1), 1), vec4(vec3(lo), 1), vec4(vec3(hi), 1)});
    }
    const std::vector<vec4> gpu = runItems(program, inputs, 12, "hull-cone");
    int cones = 0, kindMismatch = 0, differs = 0;
    for (int n = 0; n < kItems; ++n) {
        const ConeInput& x = inputs[n];
        for (int which = 0; which < 2; ++which) {
            const geometry::WedgeHull cpu = geometry::wedgeHullTruncateCone(
                geometry::wedgeHullSilhouetteCone(vec3(x.e0), vec3(x.e1), vec3(x.c), vec3(x.u),
                                                  vec3(x.v), vec3(x.w0), vec3(x.w1), which),
                vec3(x.c), vec3(x.u), vec3(x.v), vec3(x.lo), vec3(x.hi));
            const vec4* g = gpu.data() + 6 * (2 * n + which);
            const int kind = static_cast<int>(g[0].x);
            kindMismatch += kind != cpu.kind;
            if (kind != cpu.kind || cpu.kind != geometry::kWedgeHullBounded) continue;
            ++cones;
            const float scale = glm::length(vec3(x.e0)) + glm::length(vec3(x.e1)) + 1.0f;
            // The reach to within the cut's own widening (0.1 %): a nearly flat cone's l
            // (over a small determinant) amplifies the driver's rounding.
            bool d = std::abs(g[0].y - cpu.reach) > 1e-3f * cpu.reach + 1e-4f * scale ||
                     glm::length(vec3(g[1]) - cpu.apex) > 1e-5f * scale;
            for (int k = 0; k < 4; ++k)
                d = d || glm::length(vec3(g[2 + k]) - vec3(cpu.planes[k])) > 1e-4f ||
                    std::abs(g[2 + k].w - cpu.planes[k].w) > 1e-4f * scale;
            differs += d;
        }
    }
    std::printf("  %d items: %d cones; %d kinds and %d cones (planes, apex, reach) differ from "
                "the C++ build\n",
                kItems, cones, kindMismatch, differs);
    EXPECT_GT(cones, kItems);
    EXPECT_EQ(kindMismatch, 0);
    EXPECT_EQ(differs, 0);
}

TEST_F(WedgeHullShaderTest, BackFacesCoverEachViewRayThroughTheHullOnce) {
    testutil::ScratchDir dir;
    gpu::ShaderLoader loader(gpu::defaultShaderDir());
    gpu::Program program =
        loader.load({.stages = {{GL_VERTEX_SHADER, dir.write("pull.vert", kPullVert)},
                                {GL_FRAGMENT_SHADER, dir.write("count.frag", kCountFrag)}},
                     .label = "wedge-hull-count"});
    constexpr int kSize = 96;
    gpu::Texture target({.width = kSize, .height = kSize, .format = GL_R32F, .label = "count"});
    gpu::Framebuffer fbo({.attachments = {{GL_COLOR_ATTACHMENT0, &target}}, .label = "count"});
    gpu::VertexArray vao("pulled");
    constexpr gpu::PipelineState kCount{.cull = true,
                                        .cullFace = GL_FRONT, // draw back faces
                                        .blend = true,
                                        .blendSrc = GL_ONE,
                                        .blendDst = GL_ONE,
                                        .depthClamp = true};

    Rng rng(99);
    int draws = 0, insideDraws = 0, fullscreenDraws = 0, checked = 0, skipped = 0, wrong = 0;
    for (int n = 0; n < 40; ++n) {
        Item item = randomItem(rng, n);
        const CheckInput& x = item.in;
        const geometry::WedgeHull hull =
            geometry::wedgeHull(vec3(x.e0), vec3(x.e1), vec3(x.c), vec3(x.u), vec3(x.v));
        if (hull.kind == geometry::kWedgeHullDegenerate) continue;
        const dvec3 e0(vec3(x.e0)), e1(vec3(x.e1)), mid = 0.5 * (e0 + e1);
        const double size = glm::length(e1 - e0) + glm::length(mid - dvec3(vec3(x.c)));
        // Odd draws from inside: the eye on a shadow ray through the edge, looking anywhere.
        const bool inside = n % 2 == 1 && hull.kind == geometry::kWedgeHullBounded;
        dvec3 eye, target3;
        if (inside) {
            const dvec3 a = e0 + item.lambda * (e1 - e0);
            const dvec3 y =
                dvec3(vec3(x.c)) + item.s * dvec3(vec3(x.u)) + item.t * dvec3(vec3(x.v));
            eye = a + rng.uniform(0.2, 2.0) * (a - y);
            target3 = eye + rng.direction();
        } else {
            eye = mid + rng.uniform(1.5, 4.0) * size * rng.direction();
            target3 = mid + 0.3 * size * rng.direction();
        }
        const glm::dmat4 view = glm::lookAt(
            eye, target3,
            glm::abs(glm::normalize(target3 - eye).y) > 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0));
        const glm::dmat4 proj = glm::infinitePerspective(glm::radians(60.0), 1.0, 0.01 * size);
        const glm::dmat4 viewProj = proj * view;
        const glm::dmat4 inverse = glm::inverse(viewProj);

        const std::vector<vec4> edges = {x.e0, x.e1};
        gpu::Buffer edgeBuffer({.size = sizeof(vec4) * 2, .data = edges.data(), .label = "edge"});
        const float clear = 0.0f;
        glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, &clear);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
        glViewport(0, 0, kSize, kSize);
        gpu::applyState(kCount);
        glUseProgram(program.id());
        const glm::mat4 vp(viewProj);
        glProgramUniformMatrix4fv(program.id(), program.uniformLocation("viewProj"), 1, GL_FALSE,
                                  &vp[0][0]);
        glProgramUniform3fv(program.id(), program.uniformLocation("lightC"), 1, &x.c.x);
        glProgramUniform3fv(program.id(), program.uniformLocation("lightU"), 1, &x.u.x);
        glProgramUniform3fv(program.id(), program.uniformLocation("lightV"), 1, &x.v.x);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, edgeBuffer.id());
        glBindVertexArray(vao.id());
        glDrawArrays(GL_TRIANGLES, 0, geometry::kWedgeHullVertexCount);
        glBindVertexArray(0);
        glUseProgram(0);
        gpu::applyState(gpu::PipelineState{});
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
        const std::vector<float> counts = target.readFloat(1);
        ++draws;
        insideDraws += inside;
        fullscreenDraws += hull.kind == geometry::kWedgeHullFullscreen;

        // Does the ray from the eye through NDC (nx, ny) meet the hull (t in (0, inf))?
        auto meets = [&](double nx, double ny) {
            if (hull.kind == geometry::kWedgeHullFullscreen) return true;
            const glm::dvec4 far = inverse * glm::dvec4(nx, ny, 0.5, 1.0);
            const dvec3 dirn = glm::normalize(dvec3(far) / far.w - eye);
            double lo = 0.0, hi = 1e300;
            for (const vec4& pl : hull.planes) {
                const double a = glm::dot(dvec3(vec3(pl)), eye) + pl.w;
                const double b = glm::dot(dvec3(vec3(pl)), dirn);
                if (b == 0.0) {
                    if (a > 0.0) return false;
                } else if (b > 0.0) {
                    hi = std::min(hi, -a / b);
                } else {
                    lo = std::max(lo, -a / b);
                }
            }
            return lo < hi;
        };
        for (int py = 0; py < kSize; ++py) {
            for (int px = 0; px < kSize; ++px) {
                auto ndc = [&](double fx, double fy) {
                    return meets(2.0 * (px + fx) / kSize - 1.0, 2.0 * (py + fy) / kSize - 1.0);
                };
                const bool centre = ndc(0.5, 0.5);
                const int corners = ndc(0, 0) + ndc(1, 0) + ndc(0, 1) + ndc(1, 1);
                if (corners != (centre ? 4 : 0)) {
                    ++skipped;
                    continue;
                }
                const float got = counts[static_cast<std::size_t>(py) * kSize + px];
                ++checked;
                if (got != (centre ? 1.0f : 0.0f)) {
                    ++wrong;
                    ADD_FAILURE() << "draw " << n << (inside ? " (eye inside)" : "") << " pixel ("
                                  << px << ", " << py << ") count " << got << ", expected "
                                  << centre;
                    if (wrong > 10) return;
                }
            }
        }
    }
    std::printf("[ glsl     ] %d draws (%d from inside the hull, %d fullscreen): %d pixels "
                "checked, %d on outlines left out, %d wrong\n",
                draws, insideDraws, fullscreenDraws, checked, skipped, wrong);
    EXPECT_GT(insideDraws, 10);
    EXPECT_GT(fullscreenDraws, 3);
    EXPECT_EQ(wrong, 0);
}

} // namespace
