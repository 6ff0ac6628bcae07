// Move-only RAII wrappers for GL objects, created and edited with direct state access only
// (glCreate*, glNamed*, glTexture*): nothing is bound just to be edited. Each is built from a
// desc struct where zero means default, with a label for glObjectLabel.
//
//   gpu::Texture vbuf({.width = w, .height = h, .format = GL_R32F, .label = "visibility"});
#pragma once

#include <epoxy/gl.h>

#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace gpu {

// Owns one GL name; Deleter is called with it on destruction. Move-only.
template <typename Deleter> class Handle {
public:
    Handle() = default;
    explicit Handle(GLuint id) : mId(id) {}
    ~Handle() { reset(); }
    Handle(Handle&& o) noexcept : mId(std::exchange(o.mId, 0)) {}
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            reset();
            mId = std::exchange(o.mId, 0);
        }
        return *this;
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    GLuint id() const { return mId; }
    explicit operator bool() const { return mId != 0; }
    void reset() {
        if (mId) Deleter{}(mId);
        mId = 0;
    }

private:
    GLuint mId = 0;
};

struct BufferDesc {
    std::size_t size = 0;           // bytes; 0 = no storage yet (uploadResize allocates)
    const void* data = nullptr;     // initial contents (may be null)
    GLbitfield flags = GL_DYNAMIC_STORAGE_BIT; // glNamedBufferStorage flags
    const char* label = nullptr;
};

class Buffer {
public:
    Buffer() = default;
    explicit Buffer(const BufferDesc& desc);
    GLuint id() const { return mHandle.id(); }
    std::size_t size() const { return mSize; }
    void upload(const void* data, std::size_t bytes, std::size_t offset = 0);
    // Grows (reallocates, contents lost, a new GL name) if `bytes` exceeds the capacity: to at
    // least twice the old capacity, or (geometric = false) to `bytes` exactly.
    void reserve(std::size_t bytes, bool geometric = true);
    // reserve(bytes), then uploads.
    void uploadResize(const void* data, std::size_t bytes);
    template <typename T> void upload(std::span<const T> data) {
        upload(data.data(), data.size_bytes());
    }

private:
    struct Deleter {
        void operator()(GLuint id) const { glDeleteBuffers(1, &id); }
    };
    Handle<Deleter> mHandle;
    std::size_t mSize = 0;
    GLbitfield mFlags = 0;
    std::string mLabel;
};

struct TextureDesc {
    GLenum target = GL_TEXTURE_2D; // or GL_TEXTURE_2D_ARRAY (with `layers`)
    int width = 0;
    int height = 0;
    int layers = 0; // GL_TEXTURE_2D_ARRAY only: at least 1
    GLenum format = GL_RGBA8;      // sized internal format
    int levels = 1;
    GLenum minFilter = GL_NEAREST;
    GLenum magFilter = GL_NEAREST;
    GLenum wrap = GL_CLAMP_TO_EDGE; // S and T (CLAMP_TO_BORDER: the border is transparent black)
    const char* label = nullptr;
};

class Texture {
public:
    Texture() = default;
    explicit Texture(const TextureDesc& desc);
    GLuint id() const { return mHandle.id(); }
    int width() const { return mWidth; }
    int height() const { return mHeight; }
    int layers() const { return mLayers; } // 0 unless an array
    GLenum format() const { return mFormat; }
    // glGetTextureImage of level 0 (2D and rectangle textures; arrays throw) into `out` (resized); bytes per pixel from format/type, rows
    // tightly packed. Rows come in GL order: the bottom row (window y = 0) first.
    void read(GLenum format, GLenum type, std::vector<std::byte>& out) const;
    // GL_RED/RG/RGB/RGBA + GL_FLOAT, `channels` floats per pixel, bottom row first (as PFM).
    std::vector<float> readFloat(int channels) const;

private:
    struct Deleter {
        void operator()(GLuint id) const { glDeleteTextures(1, &id); }
    };
    Handle<Deleter> mHandle;
    int mWidth = 0, mHeight = 0, mLayers = 0;
    GLenum mFormat = 0;
};

// A buffer texture (GL_TEXTURE_BUFFER) over a buffer of its own. upload() replaces the buffer
// with `bytes` of `data` (none: one texel of zeros, so that a texture is bound either way) and
// views it as texels of `format`; throws GlError past GL_MAX_TEXTURE_BUFFER_SIZE texels.
class BufferTexture {
public:
    BufferTexture() = default;
    void upload(const void* data, std::size_t bytes, GLenum format, std::size_t texelBytes,
                const char* label);
    GLuint id() const { return mTexture.id(); }

private:
    struct Deleter {
        void operator()(GLuint id) const { glDeleteTextures(1, &id); }
    };
    Buffer mBuffer;
    Handle<Deleter> mTexture;
};

struct FramebufferAttachment {
    GLenum attachment = GL_COLOR_ATTACHMENT0; // or GL_DEPTH_STENCIL_ATTACHMENT, ...
    const Texture* texture = nullptr;
    int level = 0;
    int layer = -1; // one layer of an array texture; -1: the whole texture
};

struct FramebufferDesc {
    std::vector<FramebufferAttachment> attachments;
    const char* label = nullptr;
};

class Framebuffer {
public:
    Framebuffer() = default;
    // Attaches everything, sets glNamedFramebufferDrawBuffers to the colour attachments in
    // order, and throws GlError if the framebuffer is not complete.
    explicit Framebuffer(const FramebufferDesc& desc);
    GLuint id() const { return mHandle.id(); }
    // glNamedFramebufferDrawBuffers with a subset (e.g. to write one target of an MRT FBO).
    void setDrawBuffers(std::span<const GLenum> buffers);

private:
    struct Deleter {
        void operator()(GLuint id) const { glDeleteFramebuffers(1, &id); }
    };
    Handle<Deleter> mHandle;
};

class VertexArray {
public:
    VertexArray() = default;
    explicit VertexArray(const char* label);
    GLuint id() const { return mHandle.id(); }
    // Attribute `index` reads `components` values of `type` from the buffer at `binding`: float
    // types feed float inputs, integer types feed int/uint inputs unconverted (no normalising).
    void attribute(GLuint index, GLuint binding, int components, GLenum type = GL_FLOAT,
                   GLuint relativeOffset = 0);
    void vertexBuffer(GLuint binding, const Buffer& buffer, GLintptr offset, GLsizei stride);
    void elementBuffer(const Buffer& buffer);

private:
    struct Deleter {
        void operator()(GLuint id) const { glDeleteVertexArrays(1, &id); }
    };
    Handle<Deleter> mHandle;
};

class Program {
public:
    Program() = default;
    explicit Program(GLuint id) : mHandle(id) {}
    GLuint id() const { return mHandle.id(); }
    explicit operator bool() const { return static_cast<bool>(mHandle); }
    GLint uniformLocation(const char* name) const; // -1 if absent (optimised away)

private:
    struct Deleter {
        void operator()(GLuint id) const { glDeleteProgram(id); }
    };
    Handle<Deleter> mHandle;
};

class Query {
public:
    Query() = default;
    explicit Query(GLenum target); // glCreateQueries
    GLuint id() const { return mHandle.id(); }

private:
    struct Deleter {
        void operator()(GLuint id) const { glDeleteQueries(1, &id); }
    };
    Handle<Deleter> mHandle;
};

} // namespace gpu
