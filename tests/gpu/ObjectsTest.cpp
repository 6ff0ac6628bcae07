// RAII GL objects: buffers, move semantics, texture read-back, framebuffer completeness, a tiny
// draw into an R32F target, and applyState.
#include "GlTestEnv.h"

#include <gpu/gl/Debug.h>
#include <gpu/gl/Objects.h>
#include <gpu/gl/ShaderLoader.h>
#include <gpu/gl/State.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

class ObjectsTest : public GlTest {};

std::string objectLabel(GLenum kind, GLuint id) {
    char buf[128] = {};
    GLsizei length = 0;
    glGetObjectLabel(kind, id, sizeof buf, &length, buf);
    return std::string(buf, static_cast<std::size_t>(length));
}

TEST_F(ObjectsTest, BufferUploadAndReadBack) {
    std::array<std::uint32_t, 8> initial{};
    std::iota(initial.begin(), initial.end(), 10u);
    gpu::Buffer buffer({.size = sizeof initial, .data = initial.data(), .label = "numbers"});
    ASSERT_NE(buffer.id(), 0u);
    EXPECT_EQ(buffer.size(), sizeof initial);
    EXPECT_EQ(objectLabel(GL_BUFFER, buffer.id()), "numbers");

    std::array<std::uint32_t, 8> back{};
    glGetNamedBufferSubData(buffer.id(), 0, sizeof back, back.data());
    EXPECT_EQ(back, initial);

    const std::uint32_t patch[2] = {7, 9};
    buffer.upload(patch, sizeof patch, 3 * sizeof(std::uint32_t));
    glGetNamedBufferSubData(buffer.id(), 0, sizeof back, back.data());
    EXPECT_EQ(back[2], 12u);
    EXPECT_EQ(back[3], 7u);
    EXPECT_EQ(back[4], 9u);
    EXPECT_EQ(back[5], 15u);

    EXPECT_THROW(buffer.upload(patch, sizeof patch, sizeof initial), std::out_of_range);
    const std::array<float, 2> floats{1.5f, 2.5f};
    buffer.upload(std::span<const float>(floats));
    float f[2] = {};
    glGetNamedBufferSubData(buffer.id(), 0, sizeof f, f);
    EXPECT_EQ(f[0], 1.5f);
    EXPECT_EQ(f[1], 2.5f);
}

TEST_F(ObjectsTest, BufferUploadResizeGrowsGeometrically) {
    gpu::Buffer stream({.label = "stream"});
    EXPECT_EQ(stream.size(), 0u);

    std::vector<std::uint32_t> data(1000);
    std::iota(data.begin(), data.end(), 0u);
    stream.uploadResize(data.data(), 100 * sizeof(std::uint32_t));
    std::size_t first = stream.size();
    EXPECT_GE(first, 100 * sizeof(std::uint32_t));

    // Small growth beyond the capacity at least doubles it: no reallocation per extra element.
    stream.uploadResize(data.data(), first + 4);
    EXPECT_GE(stream.size(), 2 * first);
    GLuint idAfterGrow = stream.id();
    EXPECT_EQ(objectLabel(GL_BUFFER, idAfterGrow), "stream"); // label survives reallocation

    stream.uploadResize(data.data(), 10 * sizeof(std::uint32_t)); // fits: same buffer
    EXPECT_EQ(stream.id(), idAfterGrow);

    std::vector<std::uint32_t> back(10);
    glGetNamedBufferSubData(stream.id(), 0, 10 * sizeof(std::uint32_t), back.data());
    EXPECT_EQ(back, std::vector<std::uint32_t>(data.begin(), data.begin() + 10));
}

TEST_F(ObjectsTest, BufferReserveKeepsTheBufferWhereItFitsAndUploadsAtAnOffset) {
    gpu::Buffer buffer({.label = "kept"});
    buffer.reserve(64);
    const GLuint id = buffer.id();
    const std::size_t capacity = buffer.size();
    EXPECT_GE(capacity, 64u);
    buffer.reserve(capacity); // fits: the same buffer
    EXPECT_EQ(buffer.id(), id);
    const std::uint32_t a[2] = {7, 8}, b[2] = {9, 10};
    buffer.upload(a, sizeof a, 0);
    buffer.upload(b, sizeof b, sizeof a);
    std::uint32_t back[4] = {};
    glGetNamedBufferSubData(buffer.id(), 0, sizeof back, back);
    EXPECT_EQ(back[0], 7u);
    EXPECT_EQ(back[3], 10u);
    buffer.reserve(capacity + 1); // grows: at least doubled, a new name, the label kept
    EXPECT_GE(buffer.size(), 2 * capacity);
    EXPECT_EQ(objectLabel(GL_BUFFER, buffer.id()), "kept");
    const std::size_t exact = buffer.size() + 100;
    buffer.reserve(exact, false); // grows to exactly what is asked
    EXPECT_EQ(buffer.size(), exact);
}

int gDeleteCalls = 0;
struct CountingDeleter {
    void operator()(GLuint) const { ++gDeleteCalls; }
};

TEST(ObjectsHandleTest, MoveTransfersOwnershipAndDeletesOnce) {
    gDeleteCalls = 0;
    {
        gpu::Handle<CountingDeleter> a(5);
        gpu::Handle<CountingDeleter> b(std::move(a));
        EXPECT_EQ(a.id(), 0u);
        EXPECT_FALSE(a);
        EXPECT_EQ(b.id(), 5u);

        gpu::Handle<CountingDeleter> c(7);
        c = std::move(b); // releases 7, takes 5
        EXPECT_EQ(gDeleteCalls, 1);
        EXPECT_EQ(c.id(), 5u);
        EXPECT_EQ(b.id(), 0u);

        auto& alias = c;
        c = std::move(alias); // self-move keeps the name
        EXPECT_EQ(c.id(), 5u);
        EXPECT_EQ(gDeleteCalls, 1);
    }
    EXPECT_EQ(gDeleteCalls, 2); // 7 once, 5 once; moved-from handles delete nothing
}

TEST_F(ObjectsTest, MovedObjectsKeepOneLiveGlName) {
    gpu::Texture a({.width = 4, .height = 4, .format = GL_R32F, .label = "moved"});
    GLuint id = a.id();
    gpu::Texture b(std::move(a));
    EXPECT_EQ(a.id(), 0u);
    EXPECT_EQ(b.id(), id);
    EXPECT_EQ(b.width(), 4);
    EXPECT_TRUE(glIsTexture(id));

    gpu::Buffer x({.size = 4});
    gpu::Buffer y({.size = 8});
    GLuint yOld = y.id();
    y = std::move(x);
    EXPECT_EQ(x.id(), 0u);
    EXPECT_FALSE(glIsBuffer(yOld)); // the overwritten buffer was deleted
    EXPECT_TRUE(glIsBuffer(y.id()));
}

TEST_F(ObjectsTest, TextureReadFloatRoundTrip) {
    const int w = 5, h = 3; // odd width: rows are not 4-byte multiples for RGB8 below
    std::vector<float> rgba(w * h * 4);
    for (std::size_t i = 0; i < rgba.size(); ++i)
        rgba[i] = 0.125f * static_cast<float>(i) - 3.0f;
    gpu::Texture tex({.width = w, .height = h, .format = GL_RGBA32F, .label = "roundtrip"});
    EXPECT_EQ(objectLabel(GL_TEXTURE, tex.id()), "roundtrip");
    glTextureSubImage2D(tex.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, rgba.data());
    EXPECT_EQ(tex.readFloat(4), rgba);

    std::vector<float> red = tex.readFloat(1);
    ASSERT_EQ(red.size(), static_cast<std::size_t>(w * h));
    for (int i = 0; i < w * h; ++i)
        EXPECT_EQ(red[i], rgba[i * 4]);

    // Byte read of an RGB8 texture with tight rows despite the default pack alignment of 4.
    std::vector<std::uint8_t> rgb(w * h * 3);
    std::iota(rgb.begin(), rgb.end(), std::uint8_t{1});
    gpu::Texture bytes({.width = w, .height = h, .format = GL_RGB8});
    GLint unpack = 4;
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &unpack);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(bytes.id(), 0, 0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, unpack);
    std::vector<std::byte> out;
    bytes.read(GL_RGB, GL_UNSIGNED_BYTE, out);
    ASSERT_EQ(out.size(), rgb.size());
    for (std::size_t i = 0; i < rgb.size(); ++i) {
        ASSERT_EQ(static_cast<std::uint8_t>(out[i]), rgb[i]) << "byte " << i;
    }
    GLint pack = 0;
    glGetIntegerv(GL_PACK_ALIGNMENT, &pack);
    EXPECT_EQ(pack, 4); // restored
}

TEST_F(ObjectsTest, IncompleteFramebufferThrowsWithStatusName) {
    gpu::Texture colour({.width = 4, .height = 4, .format = GL_R32F});
    // A colour format cannot be a depth attachment.
    try {
        gpu::Framebuffer bad(
            {.attachments = {{GL_DEPTH_ATTACHMENT, &colour}}, .label = "colour-as-depth"});
        FAIL() << "incomplete framebuffer accepted";
    } catch (const gpu::GlError& e) {
        std::string what = e.what();
        EXPECT_NE(what.find("GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT"), std::string::npos) << what;
        EXPECT_NE(what.find("colour-as-depth"), std::string::npos) << what;
    }
    try {
        gpu::Framebuffer empty(gpu::FramebufferDesc{});
        FAIL() << "framebuffer without attachments accepted";
    } catch (const gpu::GlError& e) {
        EXPECT_NE(std::string(e.what()).find("GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT"),
                  std::string::npos)
            << e.what();
    }

    // And the valid depth-only combination is complete, with no draw buffer.
    gpu::Texture depth({.width = 4, .height = 4, .format = GL_DEPTH24_STENCIL8});
    gpu::Framebuffer ok({.attachments = {{GL_DEPTH_STENCIL_ATTACHMENT, &depth}}});
    // Draw-buffer state has no DSA query; bind only to read it.
    GLint drawBuffer = -1, readBuffer = -1;
    glBindFramebuffer(GL_FRAMEBUFFER, ok.id());
    glGetIntegerv(GL_DRAW_BUFFER0, &drawBuffer);
    glGetIntegerv(GL_READ_BUFFER, &readBuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    EXPECT_EQ(drawBuffer, GL_NONE);
    EXPECT_EQ(readBuffer, GL_NONE);
}

// Writes a temporary shader root for the draw test.
struct TempShaderDir {
    fs::path root;
    TempShaderDir() {
        root = fs::temp_directory_path() / ("penumbra-objects-test-" + std::to_string(::getpid()));
        fs::create_directories(root);
    }
    ~TempShaderDir() {
        std::error_code ec;
        fs::remove_all(root, ec);
    }
    void write(const std::string& name, const std::string& text) const {
        std::ofstream(root / name) << text;
    }
};

TEST_F(ObjectsTest, FullscreenTriangleIntoR32FTarget) {
    const int w = 8, h = 4;
    TempShaderDir dir;
    dir.write("tri.vert", "layout(location = 0) in vec2 position;\n"
                          "void main() { gl_Position = vec4(position, 0.0, 1.0); }\n");
    // Each pixel writes a value that identifies its window coordinates, so the read-back checks
    // coverage and row order (readFloat returns the bottom row first).
    dir.write("tri.frag", "uniform float scale;\n"
                          "layout(location = 0) out float value;\n"
                          "void main() { value = scale * (gl_FragCoord.x + 100.0 * "
                          "gl_FragCoord.y); }\n");
    gpu::ShaderLoader loader(dir.root);
    gpu::Program program =
        loader.load({.stages = {{GL_VERTEX_SHADER, "tri.vert"}, {GL_FRAGMENT_SHADER, "tri.frag"}},
                     .label = "tri"});
    GLint scale = program.uniformLocation("scale");
    ASSERT_GE(scale, 0);
    EXPECT_EQ(program.uniformLocation("absent"), -1);
    glProgramUniform1f(program.id(), scale, 2.0f);

    // One triangle covering the viewport: (-1,-1), (3,-1), (-1,3), drawn through an index buffer.
    const float positions[] = {-1.0f, -1.0f, 3.0f, -1.0f, -1.0f, 3.0f};
    const std::uint32_t indices[] = {0, 1, 2};
    gpu::Buffer vbo({.size = sizeof positions, .data = positions, .label = "tri-positions"});
    gpu::Buffer ibo({.size = sizeof indices, .data = indices, .label = "tri-indices"});
    gpu::VertexArray vao("tri");
    vao.attribute(0, 0, 2);
    vao.vertexBuffer(0, vbo, 0, 2 * sizeof(float));
    vao.elementBuffer(ibo);

    gpu::Texture target({.width = w, .height = h, .format = GL_R32F, .label = "tri-target"});
    gpu::Framebuffer fbo({.attachments = {{GL_COLOR_ATTACHMENT0, &target}}});
    const float clear = -1.0f;
    glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, &clear);

    gpu::applyState(gpu::PipelineState{});
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo.id());
    glViewport(0, 0, w, h);
    glUseProgram(program.id());
    glBindVertexArray(vao.id());
    glDrawElements(GL_TRIANGLES, 3, GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    gpu::checkGl("fullscreen triangle");

    std::vector<float> values = target.readFloat(1);
    ASSERT_EQ(values.size(), static_cast<std::size_t>(w * h));
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            // Pixel centres are at +0.5; all values are exact in float.
            float expected = 2.0f * ((x + 0.5f) + 100.0f * (y + 0.5f));
            EXPECT_EQ(values[y * w + x], expected) << "x=" << x << " y=" << y;
        }
    }
}

TEST_F(ObjectsTest, ApplyStateSetsEveryField) {
    gpu::PipelineState s;
    s.depthTest = true;
    s.depthFunc = GL_LEQUAL;
    s.depthWrite = true;
    s.colorWrite = false;
    s.stencilTest = true;
    s.stencilWriteMask = 0x0F;
    s.stencilFront = {GL_EQUAL, 3, 0x7F, GL_KEEP, GL_INCR_WRAP, GL_KEEP};
    s.stencilBack = {GL_NOTEQUAL, 1, 0x3F, GL_KEEP, GL_DECR_WRAP, GL_ZERO};
    s.cull = true;
    s.cullFace = GL_FRONT;
    s.blend = true;
    s.blendSrc = GL_SRC_ALPHA;
    s.blendDst = GL_ONE_MINUS_SRC_ALPHA;
    s.blendEquation = GL_MIN;
    s.polygonOffset = true;
    s.polygonOffsetFactor = 1.5f;
    s.polygonOffsetUnits = 4.0f;
    s.depthClamp = true;
    s.scissor = true;
    // Stencil reference queries are clamped to the bound framebuffer's stencil bits, and the
    // surfaceless default framebuffer has none: query with a stencil target bound.
    gpu::Texture depthStencil({.width = 4, .height = 4, .format = GL_DEPTH24_STENCIL8});
    gpu::Framebuffer fbo({.attachments = {{GL_DEPTH_STENCIL_ATTACHMENT, &depthStencil}}});
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    gpu::applyState(s);

    auto get = [](GLenum name) {
        GLint v = 0;
        glGetIntegerv(name, &v);
        return v;
    };
    EXPECT_TRUE(glIsEnabled(GL_DEPTH_TEST));
    EXPECT_EQ(get(GL_DEPTH_FUNC), GL_LEQUAL);
    EXPECT_EQ(get(GL_DEPTH_WRITEMASK), GL_TRUE);
    GLboolean mask[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
    glGetBooleanv(GL_COLOR_WRITEMASK, mask);
    EXPECT_FALSE(mask[0] || mask[1] || mask[2] || mask[3]);
    EXPECT_TRUE(glIsEnabled(GL_STENCIL_TEST));
    EXPECT_EQ(get(GL_STENCIL_WRITEMASK), 0x0F);
    EXPECT_EQ(get(GL_STENCIL_BACK_WRITEMASK), 0x0F);
    EXPECT_EQ(get(GL_STENCIL_FUNC), GL_EQUAL);
    EXPECT_EQ(get(GL_STENCIL_REF), 3);
    EXPECT_EQ(get(GL_STENCIL_VALUE_MASK), 0x7F);
    EXPECT_EQ(get(GL_STENCIL_PASS_DEPTH_FAIL), GL_INCR_WRAP);
    EXPECT_EQ(get(GL_STENCIL_BACK_FUNC), GL_NOTEQUAL);
    EXPECT_EQ(get(GL_STENCIL_BACK_REF), 1);
    EXPECT_EQ(get(GL_STENCIL_BACK_VALUE_MASK), 0x3F);
    EXPECT_EQ(get(GL_STENCIL_BACK_PASS_DEPTH_FAIL), GL_DECR_WRAP);
    EXPECT_EQ(get(GL_STENCIL_BACK_PASS_DEPTH_PASS), GL_ZERO);
    EXPECT_TRUE(glIsEnabled(GL_CULL_FACE));
    EXPECT_EQ(get(GL_CULL_FACE_MODE), GL_FRONT);
    EXPECT_TRUE(glIsEnabled(GL_BLEND));
    EXPECT_EQ(get(GL_BLEND_SRC_RGB), GL_SRC_ALPHA);
    EXPECT_EQ(get(GL_BLEND_DST_ALPHA), GL_ONE_MINUS_SRC_ALPHA);
    EXPECT_EQ(get(GL_BLEND_EQUATION_RGB), GL_MIN);
    EXPECT_TRUE(glIsEnabled(GL_POLYGON_OFFSET_FILL));
    GLfloat factor = 0, units = 0;
    glGetFloatv(GL_POLYGON_OFFSET_FACTOR, &factor);
    glGetFloatv(GL_POLYGON_OFFSET_UNITS, &units);
    EXPECT_EQ(factor, 1.5f);
    EXPECT_EQ(units, 4.0f);
    EXPECT_TRUE(glIsEnabled(GL_DEPTH_CLAMP));
    EXPECT_TRUE(glIsEnabled(GL_SCISSOR_TEST));

    // And the default state puts everything back: the baseline passes start from.
    gpu::applyState(gpu::PipelineState{});
    EXPECT_FALSE(glIsEnabled(GL_DEPTH_TEST));
    EXPECT_FALSE(glIsEnabled(GL_STENCIL_TEST));
    EXPECT_FALSE(glIsEnabled(GL_CULL_FACE));
    EXPECT_FALSE(glIsEnabled(GL_BLEND));
    EXPECT_FALSE(glIsEnabled(GL_POLYGON_OFFSET_FILL));
    EXPECT_FALSE(glIsEnabled(GL_DEPTH_CLAMP));
    EXPECT_FALSE(glIsEnabled(GL_SCISSOR_TEST));
    EXPECT_EQ(get(GL_DEPTH_WRITEMASK), GL_FALSE);
    glGetBooleanv(GL_COLOR_WRITEMASK, mask);
    EXPECT_TRUE(mask[0] && mask[1] && mask[2] && mask[3]);
    EXPECT_EQ(get(GL_STENCIL_WRITEMASK), 0xFF);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

} // namespace
