// shaders/shared/Parts.h on the driver: a compute shader runs edgeParts4 (and edgePartSet for
// every R) over random lights, edges and points and the results match the same source
// compiled as C++ (geometry/shadow/Parts.h) up to the driver's rounding (fused multiply-adds, its own division).
#include "TestRandom.h"
#include "GlTestEnv.h"
#include "ScratchDir.h"

#include <geometry/shadow/Coverage.h>
#include <geometry/shadow/Parts.h>
#include <gpu/gl/Objects.h>
#include <gpu/gl/ShaderLoader.h>

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

// vec4s per item: coverage, bounds[4], (windings[q], 0) for q = 0..3.
constexpr int kStride = 9;

const char* kPartsComp = R"(#include "shared/Coverage.h"
#include "shared/Parts.h"
layout(local_size_x = 64) in;
struct PartsInput {
    vec4 e0;
    vec4 e1;
    vec4 c;
    vec4 u;
    vec4 v;
    vec4 p;
};
layout(std430, binding = 0) readonly buffer Inputs { PartsInput inputs[]; };
layout(std430, binding = 1) writeonly buffer Outputs { vec4 outputs[]; };
uniform uint count;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    PartsInput x = inputs[i];
    CoverageLight light = coverageLight(x.c.xyz, x.u.xyz, x.v.xyz);
    EdgeParts4 parts = edgeParts4(x.p.xyz, x.e0.xyz, x.e1.xyz, light);
    uint base = i * 9u;
    outputs[base] = parts.coverage;
    for (int q = 0; q < 4; ++q) {
        outputs[base + 1u + uint(q)] = parts.bounds[q];
        outputs[base + 5u + uint(q)] = vec4(parts.windings[q], 0.0);
    }
}
)";

struct PartsInput {
    vec4 e0, e1, c, u, v, p;
};
static_assert(sizeof(PartsInput) == 6 * 16, "PartsInput must match std430");

using testutil::Rng;

// A random light; p and the edge on the same side of it, the edge mostly between them.
// `magnification`: 1 / the nearest end's distance to p's level (relative to p's height).
PartsInput randomInput(Rng& rng, double& magnification) {
    magnification = 1.0;
    const dvec3 c(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3));
    const dvec3 a = rng.direction();
    const dvec3 b = glm::normalize(glm::cross(a, rng.direction()));
    const dvec3 u = a * rng.uniform(0.2, 1.5), v = b * rng.uniform(0.2, 1.5);
    const dvec3 n = glm::normalize(glm::cross(u, v));
    auto at = [&](double s, double t, double h) { return c + s * u + t * v + h * n; };
    const double side = rng.uniform(0, 1) < 0.5 ? -1.0 : 1.0;
    const double hp = rng.uniform(1, 6);
    const dvec3 p = at(rng.uniform(-3, 3), rng.uniform(-3, 3), side * hp);
    auto end = [&] { // projecting near the light (exactly onto y where between the two)
        const dvec3 y = at(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), 0.0);
        const double lambda = rng.uniform(-0.1, 1.1);
        magnification = std::max(magnification, 1.0 / std::max(std::abs(1.0 - lambda), 1e-4));
        return y + lambda * (p - y);
    };
    const dvec3 e0 = end(), e1 = end();
    return {vec4(vec3(e0), 1), vec4(vec3(e1), 1), vec4(vec3(c), 1),
            vec4(vec3(u), 0),  vec4(vec3(v), 0),  vec4(vec3(p), 1)};
}

class PartsShaderTest : public GlTest {};

TEST_F(PartsShaderTest, ComputeMatchesTheCppBuild) {
    testutil::ScratchDir dir;
    gpu::ShaderLoader loader(gpu::defaultShaderDir());
    gpu::Program program =
        loader.load({.stages = {{GL_COMPUTE_SHADER, dir.write("parts.comp", kPartsComp)}},
                     .label = "parts-check"});
    ASSERT_TRUE(program);

    Rng rng(0x5a17);
    constexpr int kItems = 8000;
    std::vector<PartsInput> inputs;
    std::vector<double> magnification(kItems);
    for (int n = 0; n < kItems; ++n)
        inputs.push_back(randomInput(rng, magnification[n]));
    inputs[0].e1 = inputs[0].e0; // a degenerate edge: nothing anywhere
    gpu::Buffer in({.size = inputs.size() * sizeof(PartsInput),
                    .data = inputs.data(),
                    .label = "parts-check-in"});
    gpu::Buffer out({.size = inputs.size() * kStride * sizeof(vec4), .label = "parts-check-out"});
    glUseProgram(program.id());
    glProgramUniform1ui(program.id(), program.uniformLocation("count"), kItems);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
    glDispatchCompute((kItems + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<vec4> gpu(static_cast<std::size_t>(kItems) * kStride);
    glGetNamedBufferSubData(out.id(), 0, static_cast<GLsizeiptr>(gpu.size() * sizeof(vec4)),
                            gpu.data());
    glUseProgram(0);
    ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));

    // The driver's rounding against the twin's: a few ulps of the inputs of the projection and
    // the clip, below the float-vs-double tolerances of tests/geometry/shadow/PartsTest.cpp (1e-4),
    // times the magnification of an end near p's level; ends within 1e-3 of it only counted.
    constexpr double kTolerance = 1e-5;
    constexpr double kMaxMagnification = 1e3;
    int illConditioned = 0;
    double maxCoverage = 0.0, maxBounds = 0.0; // over magnification
    int nonZero = 0, nonEmpty = 0, emptinessFlips = 0, windingFlips = 0, inside = 0;
    int coverageOff = 0, boundsOff = 0;
    for (int n = 0; n < kItems; ++n) {
        const PartsInput& x = inputs[n];
        const vec4* g = gpu.data() + static_cast<std::size_t>(n) * kStride;
        const geometry::CoverageLight light =
            geometry::coverageLight(vec3(x.c), vec3(x.u), vec3(x.v));
        const geometry::EdgeParts4 cpu =
            geometry::edgeParts4(vec3(x.p), vec3(x.e0), vec3(x.e1), light);
        if (magnification[n] > kMaxMagnification) {
            ++illConditioned;
            continue;
        }
        const double tolerance = kTolerance * magnification[n];
        if (n == 0) {
            EXPECT_EQ(g[0], vec4(0.0f));
            for (int q = 0; q < 4; ++q)
                EXPECT_EQ(g[1 + q], vec4(1.0f, 1.0f, 0.0f, 0.0f));
        }
        for (int q = 0; q < 4; ++q) {
            nonZero += cpu.coverage[q] != 0.0f;
            const double dc = std::abs(double(g[0][q]) - double(cpu.coverage[q]));
            maxCoverage = std::max(maxCoverage, dc / magnification[n]);
            coverageOff += dc > tolerance;

            const vec4 b = g[1 + q], r = cpu.bounds[q];
            const bool gpuEmpty = b.x > b.z || b.y > b.w, cpuEmpty = r.x > r.z || r.y > r.w;
            if (gpuEmpty != cpuEmpty) {
                ++emptinessFlips;
            } else if (!cpuEmpty) {
                ++nonEmpty;
                const vec4 d = glm::abs(b - r);
                const double m = std::max({d.x, d.y, d.z, d.w});
                maxBounds = std::max(maxBounds, m / magnification[n]);
                boundsOff += m > tolerance;
            }

            for (int c = 0; c < 3; ++c) {
                inside += cpu.windings[q][c] != 0.0f;
                windingFlips += g[5 + q][c] != cpu.windings[q][c];
            }
        }
    }
    std::printf("[ glsl     ] %d edges: coverage %d non-zero, max |gpu - cpu| / magnification %.2g "
                "(%d over %.0e); "
                "bounds %d non-empty, max %.2g (%d over), %d emptiness flips; corners %d in R_e, "
                "%d flips; %d edges with an end within 1e-3 of p's level not compared\n",
                kItems, nonZero, maxCoverage, coverageOff, kTolerance, nonEmpty, maxBounds,
                boundsOff, emptinessFlips, inside, windingFlips, illConditioned);
    EXPECT_GT(nonZero, kItems);
    EXPECT_GT(nonEmpty, kItems / 2);
    EXPECT_GT(inside, kItems / 4);
    // A value within rounding of a threshold (a clip, a corner on R_e's line) may go either way.
    EXPECT_LE(coverageOff, kItems / 1000);
    EXPECT_LE(boundsOff, kItems / 1000);
    EXPECT_LE(emptinessFlips, kItems / 1000);
    EXPECT_LE(windingFlips, kItems / 1000);
}

// edgePartSet: vec4s per item coverage, momentX, momentY, bounds[4], windings.
constexpr int kSetStride = 8;

const char* kPartSetComp = R"(#include "shared/Coverage.h"
#include "shared/Parts.h"
layout(local_size_x = 64) in;
struct PartsInput {
    vec4 e0;
    vec4 e1;
    vec4 c;
    vec4 u;
    vec4 v;
    vec4 p;
};
layout(std430, binding = 0) readonly buffer Inputs { PartsInput inputs[]; };
layout(std430, binding = 1) writeonly buffer Outputs { vec4 outputs[]; };
uniform uint count;
uniform int parts;
uniform int set;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    PartsInput x = inputs[i];
    CoverageLight light = coverageLight(x.c.xyz, x.u.xyz, x.v.xyz);
    EdgePartSet e = edgePartSet(x.p.xyz, x.e0.xyz, x.e1.xyz, light, parts, set);
    uint base = i * 8u;
    outputs[base] = e.coverage;
    outputs[base + 1u] = e.momentX;
    outputs[base + 2u] = e.momentY;
    for (int k = 0; k < 4; ++k) outputs[base + 3u + uint(k)] = e.bounds[k];
    outputs[base + 7u] = e.windings;
}
)";

TEST_F(PartsShaderTest, PartSetComputeMatchesTheCppBuildForEveryR) {
    testutil::ScratchDir dir;
    gpu::ShaderLoader loader(gpu::defaultShaderDir());
    gpu::Program program =
        loader.load({.stages = {{GL_COMPUTE_SHADER, dir.write("part-set.comp", kPartSetComp)}},
                     .label = "part-set-check"});
    ASSERT_TRUE(program);

    Rng rng(0x5e75);
    constexpr int kItems = 4000;
    std::vector<PartsInput> inputs;
    std::vector<double> magnification(kItems);
    for (int n = 0; n < kItems; ++n)
        inputs.push_back(randomInput(rng, magnification[n]));
    gpu::Buffer in({.size = inputs.size() * sizeof(PartsInput),
                    .data = inputs.data(),
                    .label = "part-set-check-in"});
    gpu::Buffer out(
        {.size = inputs.size() * kSetStride * sizeof(vec4), .label = "part-set-check-out"});
    constexpr double kTolerance = 1e-5; // as above, times the magnification
    constexpr double kMaxMagnification = 1e3;
    for (const auto& [parts, set] :
         {std::pair{1, 0}, std::pair{4, 0}, std::pair{8, 0}, std::pair{8, 1}}) {
        glUseProgram(program.id());
        glProgramUniform1ui(program.id(), program.uniformLocation("count"), kItems);
        glProgramUniform1i(program.id(), program.uniformLocation("parts"), parts);
        glProgramUniform1i(program.id(), program.uniformLocation("set"), set);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
        glDispatchCompute((kItems + 63) / 64, 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<vec4> gpu(static_cast<std::size_t>(kItems) * kSetStride);
        glGetNamedBufferSubData(out.id(), 0, static_cast<GLsizeiptr>(gpu.size() * sizeof(vec4)),
                                gpu.data());
        glUseProgram(0);
        ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));

        int nonZero = 0, valuesOff = 0, emptinessFlips = 0, windingFlips = 0, inside = 0;
        double maxValue = 0.0;
        const int count = parts == 1 ? 1 : 4;
        for (int n = 0; n < kItems; ++n) {
            if (magnification[n] > kMaxMagnification) continue;
            const PartsInput& x = inputs[n];
            const vec4* g = gpu.data() + static_cast<std::size_t>(n) * kSetStride;
            const geometry::EdgePartSet cpu = geometry::edgePartSet(
                vec3(x.p), vec3(x.e0), vec3(x.e1),
                geometry::coverageLight(vec3(x.c), vec3(x.u), vec3(x.v)), parts, set);
            const double tolerance = kTolerance * magnification[n];
            for (int k = 0; k < count; ++k) {
                nonZero += cpu.coverage[k] != 0.0f;
                const double d = std::max({std::abs(g[0][k] - cpu.coverage[k]),
                                           std::abs(g[1][k] - cpu.momentX[k]),
                                           std::abs(g[2][k] - cpu.momentY[k])});
                const vec4 b = g[3 + k], r = cpu.bounds[k];
                const bool gpuEmpty = b.x > b.z || b.y > b.w, cpuEmpty = r.x > r.z || r.y > r.w;
                double db = 0.0;
                if (gpuEmpty != cpuEmpty) {
                    ++emptinessFlips;
                } else if (!cpuEmpty) {
                    const vec4 e = glm::abs(b - r);
                    db = std::max({e.x, e.y, e.z, e.w});
                }
                maxValue = std::max(maxValue, std::max(d, db) / magnification[n]);
                valuesOff += std::max(d, db) > tolerance;
                inside += cpu.windings[k] != 0.0f;
                windingFlips += g[7][k] != cpu.windings[k];
            }
            for (int k = count; k < 4; ++k) { // unused parts of the set stay empty
                EXPECT_EQ(g[0][k], 0.0f);
                EXPECT_EQ(g[3 + k], vec4(1.0f, 1.0f, 0.0f, 0.0f));
            }
        }
        std::printf("[ glsl     ] edgePartSet R = %d set %d: %d coverages non-zero, max "
                    "|gpu - cpu| / magnification %.2g (%d over %.0e), %d emptiness flips, "
                    "windings %d non-zero, %d differ\n",
                    parts, set, nonZero, maxValue, valuesOff, kTolerance, emptinessFlips, inside,
                    windingFlips);
        EXPECT_GT(nonZero, kItems / 4);
        EXPECT_GT(inside, kItems / 8);
        EXPECT_LE(valuesOff, kItems / 1000);
        EXPECT_LE(emptinessFlips, kItems / 1000);
        EXPECT_LE(windingFlips, kItems / 1000);
    }
}

} // namespace
