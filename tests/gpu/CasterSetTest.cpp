// The casters' GPU data (gpu/src/engine/CasterSet.h) and the vertex-pulled light-centre volumes:
// - the std430 structs shared through shaders/lib/Bindings.h have the member offsets the linked
//   GLSL program reports (GL_OFFSET), so C++ and GLSL cannot drift;
// - every group's volume drawn from caps by reference and sides from directed edges is closed:
//   counting every face along each eye ray (z-fail with the surface at the near plane), the
//   count returns to zero for a camera outside all volumes, and is non-zero everywhere for a
//   camera inside one.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"

#include "engine/CasterSet.h"
#include "engine/ShaderBindings.h"
#include "engine/Targets.h"
#include "passes/StencilVolumePass.h"

#include <geometry/scene/Scene.h>
#include <geometry/reference/Framing.h>
#include <gpu/gl/ShaderLoader.h>
#include <gpu/gl/State.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cstddef>
#include <filesystem>
#include <fstream>

namespace {

namespace fs = std::filesystem;

// A property (GL_OFFSET, GL_TOP_LEVEL_ARRAY_STRIDE) of a buffer variable of the linked program;
// -1 when the program has no such variable.
GLint bufferVariable(GLuint program, const char* name, GLenum prop) {
    const GLuint index = glGetProgramResourceIndex(program, GL_BUFFER_VARIABLE, name);
    if (index == GL_INVALID_INDEX) return -1;
    GLint value = -1;
    glGetProgramResourceiv(program, GL_BUFFER_VARIABLE, index, 1, &prop, 1, nullptr, &value);
    return value;
}

GLint bufferVariableOffset(GLuint program, const char* name) {
    return bufferVariable(program, name, GL_OFFSET);
}

GLint arrayStride(GLuint program, const char* name) {
    return bufferVariable(program, name, GL_TOP_LEVEL_ARRAY_STRIDE);
}

} // namespace

class CasterSetGl : public GlTest {};

TEST_F(CasterSetGl, SharedStructOffsetsMatchTheLinkedProgram) {
    // A compute shader that reads every member, so that none is optimised out of the interface.
    const fs::path dir = fs::temp_directory_path() / "penumbra-layout-probe";
    fs::create_directories(dir);
    fs::remove(dir / "lib");
    fs::create_directory_symlink(gpu::defaultShaderDir() / "lib", dir / "lib");
    std::ofstream(dir / "probe.comp") << R"(
#include "lib/Bindings.h"
#include "lib/Casters.glsl"
layout(local_size_x = 1) in;
layout(std430, binding = 7) buffer Sink { vec4 sink[]; };
void main() {
    GpuEdge e = edges[gl_GlobalInvocationID.x];
    GpuGroup g = groups[gl_GlobalInvocationID.x];
    sink[0] = vec4(float(e.v0 + e.v1 + e.group + e.flags), float(g.firstEdge + g.edgeCount),
                   float(g.firstTriangle + g.triangleCount), 0.0) + g.influenceMin +
              g.influenceMax + weldedPositions[weldedIndices[capTriangles[0]]];
}
)";
    gpu::ShaderLoader loader(dir);
    const gpu::Program program =
        loader.load({.stages = {{GL_COMPUTE_SHADER, "probe.comp"}}, .label = "layout-probe"});
    const GLuint p = program.id();
    using gpu::shader::GpuEdge;
    using gpu::shader::GpuGroup;
    EXPECT_EQ(bufferVariableOffset(p, "edges[0].v0"), GLint(offsetof(GpuEdge, v0)));
    EXPECT_EQ(bufferVariableOffset(p, "edges[0].v1"), GLint(offsetof(GpuEdge, v1)));
    EXPECT_EQ(bufferVariableOffset(p, "edges[0].group"), GLint(offsetof(GpuEdge, group)));
    EXPECT_EQ(bufferVariableOffset(p, "edges[0].flags"), GLint(offsetof(GpuEdge, flags)));
    EXPECT_EQ(arrayStride(p, "edges[0].v0"), GLint(sizeof(GpuEdge)));
    EXPECT_EQ(bufferVariableOffset(p, "groups[0].influenceMin"),
              GLint(offsetof(GpuGroup, influenceMin)));
    EXPECT_EQ(bufferVariableOffset(p, "groups[0].influenceMax"),
              GLint(offsetof(GpuGroup, influenceMax)));
    EXPECT_EQ(bufferVariableOffset(p, "groups[0].firstEdge"), GLint(offsetof(GpuGroup, firstEdge)));
    EXPECT_EQ(bufferVariableOffset(p, "groups[0].edgeCount"), GLint(offsetof(GpuGroup, edgeCount)));
    EXPECT_EQ(bufferVariableOffset(p, "groups[0].firstTriangle"),
              GLint(offsetof(GpuGroup, firstTriangle)));
    EXPECT_EQ(bufferVariableOffset(p, "groups[0].triangleCount"),
              GLint(offsetof(GpuGroup, triangleCount)));
    EXPECT_EQ(arrayStride(p, "groups[0].firstEdge"), GLint(sizeof(GpuGroup)));
    fs::remove_all(dir);
}

namespace {

// Draws the light centre's volumes of every caster with the depth buffer at the near plane, so
// that z-fail counts every face along each eye ray, and returns the stencil values.
std::vector<std::uint8_t> fullRayCounts(const geometry::Scene& scene, const glm::vec3& eye,
                                        const glm::vec3& target, int size) {
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Targets targets;
    targets.resize(size, size);
    gpu::CasterSet casters(scene);
    casters.update(scene.light, scene.bounds());

    gpu::shader::FrameUniforms u{};
    const float zNear = 1e-3f;
    glm::mat4 proj(0.0f); // reversed Z, infinite far plane (as the renderer)
    const float f = 1.0f / std::tan(glm::radians(35.0f));
    proj[0][0] = f;
    proj[1][1] = f;
    proj[2][3] = -1.0f;
    proj[3][2] = zNear;
    const glm::vec3 forward = glm::normalize(target - eye);
    const glm::vec3 up = std::abs(forward.y) > 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    u.viewProj = proj * glm::lookAt(eye, target, up);
    u.eye = glm::vec4(eye, 1.0f);
    u.lightCenter = glm::vec4(scene.light.center, 1.0f);
    gpu::Buffer ubo({.size = sizeof(u), .data = &u, .label = "test-frame"});
    glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_FRAME_UBO, ubo.id());
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);

    glDepthMask(GL_TRUE);
    glStencilMask(0xFF);
    glClearNamedFramebufferfi(targets.visibilityFbo.id(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
    casters.bind();
    gpu::StencilVolumePass pass(shaders);
    gpu::CasterRange all;
    all.triangleCount = casters.triangleCount();
    all.edgeCount = casters.edgeCount();
    pass.drawCentre(targets, all);
    gpu::checkGl("volumes");

    std::vector<std::byte> raw;
    targets.depthStencil.read(GL_DEPTH_STENCIL, GL_FLOAT_32_UNSIGNED_INT_24_8_REV, raw);
    std::vector<std::uint8_t> stencil(static_cast<std::size_t>(size) * size);
    for (std::size_t i = 0; i < stencil.size(); ++i)
        stencil[i] = static_cast<std::uint8_t>(raw[8 * i + 4]);
    gpu::applyState(gpu::PipelineState{}); // later tests in this process expect the defaults
    return stencil;
}

std::size_t nonZero(const std::vector<std::uint8_t>& s) {
    return static_cast<std::size_t>(std::count_if(s.begin(), s.end(), [](auto v) { return v; }));
}

} // namespace

TEST_F(CasterSetGl, VolumesOfClosedAndOpenCastersAreClosed) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("demo.json").string());
    // Just below the light centre: lit, so outside every volume; looking across the scene.
    const glm::vec3 eye = scene.light.center - glm::vec3(0.0f, 0.05f, 0.0f);
    const auto counts = fullRayCounts(scene, eye, glm::vec3(0.0f), 96);
    EXPECT_EQ(nonZero(counts), 0u) << "rays whose face count does not return to zero";
}

TEST_F(CasterSetGl, CameraInsideAVolumeCountsOnEveryRay) {
    // The test above could pass with nothing drawn: a camera in the umbra of the parallel square
    // sees a non-zero count along every ray (each ray leaves the volume once, net).
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("parallel-square.json").string());
    const auto counts = fullRayCounts(scene, glm::vec3(0.0f, 0.5f, 0.0f),
                                      glm::vec3(1.0f, 0.2f, 0.3f), 64);
    EXPECT_EQ(nonZero(counts), counts.size());
}

TEST_F(CasterSetGl, VolumesOfAnOpenLevelAreClosed) {
    const auto path = fs::path(PENUMBRA_SHARED_DIR) / "levels" / "oa_dm4.glb";
    ASSERT_TRUE(fs::exists(path)) << path << " missing (the shared levels are part of the suite)";
    const geometry::Scene scene = testutil::framedLevel("levels/oa_dm4.glb");
    const glm::vec3 eye = scene.light.center - glm::vec3(0.0f, 0.02f, 0.0f) *
                                                   glm::length(scene.bounds().extent());
    const auto counts = fullRayCounts(scene, eye, scene.camera.target, 96);
    EXPECT_EQ(nonZero(counts), 0u);
}
