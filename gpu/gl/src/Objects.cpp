// RAII GL objects, created and edited with direct state access only.
#include <gpu/gl/Debug.h>
#include <gpu/gl/Objects.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace gpu {

namespace {

void label(GLenum kind, GLuint id, const char* text) {
    if (text && *text) glObjectLabel(kind, id, -1, text);
}

std::string describe(const char* kind, const std::string& label) {
    return label.empty() ? std::string(kind) : std::string(kind) + " '" + label + "'";
}

const char* framebufferStatusName(GLenum status) {
    switch (status) {
    case GL_FRAMEBUFFER_COMPLETE:
        return "GL_FRAMEBUFFER_COMPLETE";
    case GL_FRAMEBUFFER_UNDEFINED:
        return "GL_FRAMEBUFFER_UNDEFINED";
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT:
        return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT:
        return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER:
        return "GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER";
    case GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER:
        return "GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER";
    case GL_FRAMEBUFFER_UNSUPPORTED:
        return "GL_FRAMEBUFFER_UNSUPPORTED";
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE:
        return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
    case GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS:
        return "GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS";
    case 0:
        return "0 (glCheckNamedFramebufferStatus failed)";
    default:
        return "unknown framebuffer status";
    }
}

bool isColorAttachment(GLenum attachment) {
    return attachment >= GL_COLOR_ATTACHMENT0 && attachment <= GL_COLOR_ATTACHMENT31;
}

int componentCount(GLenum format) {
    switch (format) {
    case GL_RED:
    case GL_GREEN:
    case GL_BLUE:
    case GL_RED_INTEGER:
    case GL_GREEN_INTEGER:
    case GL_BLUE_INTEGER:
    case GL_DEPTH_COMPONENT:
    case GL_STENCIL_INDEX:
    case GL_DEPTH_STENCIL:
        return 1;
    case GL_RG:
    case GL_RG_INTEGER:
        return 2;
    case GL_RGB:
    case GL_BGR:
    case GL_RGB_INTEGER:
    case GL_BGR_INTEGER:
        return 3;
    case GL_RGBA:
    case GL_BGRA:
    case GL_RGBA_INTEGER:
    case GL_BGRA_INTEGER:
        return 4;
    default:
        return 0;
    }
}

// Bytes per pixel for a client format/type pair; packed types hold a whole pixel.
std::size_t pixelBytes(GLenum format, GLenum type) {
    switch (type) {
    case GL_UNSIGNED_BYTE_3_3_2:
    case GL_UNSIGNED_BYTE_2_3_3_REV:
        return 1;
    case GL_UNSIGNED_SHORT_5_6_5:
    case GL_UNSIGNED_SHORT_5_6_5_REV:
    case GL_UNSIGNED_SHORT_4_4_4_4:
    case GL_UNSIGNED_SHORT_4_4_4_4_REV:
    case GL_UNSIGNED_SHORT_5_5_5_1:
    case GL_UNSIGNED_SHORT_1_5_5_5_REV:
        return 2;
    case GL_UNSIGNED_INT_8_8_8_8:
    case GL_UNSIGNED_INT_8_8_8_8_REV:
    case GL_UNSIGNED_INT_10_10_10_2:
    case GL_UNSIGNED_INT_2_10_10_10_REV:
    case GL_UNSIGNED_INT_24_8:
    case GL_UNSIGNED_INT_10F_11F_11F_REV:
    case GL_UNSIGNED_INT_5_9_9_9_REV:
        return 4;
    case GL_FLOAT_32_UNSIGNED_INT_24_8_REV:
        return 8;
    default:
        break;
    }
    std::size_t component = 0;
    switch (type) {
    case GL_UNSIGNED_BYTE:
    case GL_BYTE:
        component = 1;
        break;
    case GL_UNSIGNED_SHORT:
    case GL_SHORT:
    case GL_HALF_FLOAT:
        component = 2;
        break;
    case GL_UNSIGNED_INT:
    case GL_INT:
    case GL_FLOAT:
        component = 4;
        break;
    default:
        return 0;
    }
    return component * static_cast<std::size_t>(componentCount(format));
}

// glGetTextureImage writes through the pack state: force tight rows and client memory for the
// duration of a read, restoring whatever the caller had.
class PackStateGuard {
public:
    PackStateGuard() {
        glGetIntegerv(GL_PACK_ALIGNMENT, &mAlignment);
        glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &mPackBuffer);
        glGetIntegerv(GL_PACK_ROW_LENGTH, &mRowLength);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glPixelStorei(GL_PACK_ROW_LENGTH, 0);
        if (mPackBuffer) glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    }
    ~PackStateGuard() {
        glPixelStorei(GL_PACK_ALIGNMENT, mAlignment);
        glPixelStorei(GL_PACK_ROW_LENGTH, mRowLength);
        if (mPackBuffer) glBindBuffer(GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(mPackBuffer));
    }
    PackStateGuard(const PackStateGuard&) = delete;
    PackStateGuard& operator=(const PackStateGuard&) = delete;

private:
    GLint mAlignment = 4, mPackBuffer = 0, mRowLength = 0;
};

} // namespace

// ---------------------------------------------------------------------------------------------
// Buffer

Buffer::Buffer(const BufferDesc& desc)
    : mSize(desc.size), mFlags(desc.flags), mLabel(desc.label ? desc.label : "") {
    if (desc.data && desc.size == 0) {
        throw std::invalid_argument(describe("Buffer", mLabel) + ": data given with size 0");
    }
    GLuint id = 0;
    glCreateBuffers(1, &id);
    mHandle = Handle<Deleter>(id);
    // Immutable storage cannot have size 0; an empty buffer gets storage on first uploadResize.
    if (mSize > 0) {
        glNamedBufferStorage(id, static_cast<GLsizeiptr>(mSize), desc.data, mFlags);
    }
    label(GL_BUFFER, id, desc.label);
}

void Buffer::upload(const void* data, std::size_t bytes, std::size_t offset) {
    if (bytes == 0) return;
    if (!mHandle || offset + bytes > mSize) {
        throw std::out_of_range(describe("Buffer", mLabel) + ": upload of " +
                                std::to_string(bytes) + " bytes at offset " +
                                std::to_string(offset) + " exceeds size " + std::to_string(mSize));
    }
    if (!(mFlags & GL_DYNAMIC_STORAGE_BIT)) {
        throw std::logic_error(describe("Buffer", mLabel) +
                               ": upload needs GL_DYNAMIC_STORAGE_BIT in BufferDesc::flags");
    }
    glNamedBufferSubData(mHandle.id(), static_cast<GLintptr>(offset),
                         static_cast<GLsizeiptr>(bytes), data);
}

void Buffer::reserve(std::size_t bytes, bool geometric) {
    if (bytes > mSize || !mHandle) {
        // Geometric growth: streaming buffers (silhouette edges per frame) grow a few times and
        // then settle, instead of reallocating whenever the count creeps up.
        std::size_t capacity = std::max<std::size_t>({bytes, geometric ? mSize * 2 : 0, 256});
        GLbitfield flags = mFlags | GL_DYNAMIC_STORAGE_BIT;
        GLuint id = 0;
        glCreateBuffers(1, &id);
        glNamedBufferStorage(id, static_cast<GLsizeiptr>(capacity), nullptr, flags);
        label(GL_BUFFER, id, mLabel.c_str());
        // The GL name changes: vertex arrays that referenced the old buffer must be re-pointed.
        mHandle = Handle<Deleter>(id);
        mSize = capacity;
        mFlags = flags;
    }
}

void Buffer::uploadResize(const void* data, std::size_t bytes) {
    reserve(bytes);
    upload(data, bytes, 0);
}

// ---------------------------------------------------------------------------------------------
// Texture

Texture::Texture(const TextureDesc& desc)
    : mWidth(desc.width), mHeight(desc.height), mFormat(desc.format) {
    if (desc.width <= 0 || desc.height <= 0) {
        throw std::invalid_argument(describe("Texture", desc.label ? desc.label : "") + ": size " +
                                    std::to_string(desc.width) + "x" + std::to_string(desc.height) +
                                    " is empty");
    }
    const bool array = desc.target == GL_TEXTURE_2D_ARRAY;
    if (desc.target != GL_TEXTURE_2D && desc.target != GL_TEXTURE_RECTANGLE && !array) {
        // Cube, 3D and multisample targets need a depth/sample count this desc does not carry.
        throw std::invalid_argument(
            describe("Texture", desc.label ? desc.label : "") +
            ": only GL_TEXTURE_2D, GL_TEXTURE_2D_ARRAY and GL_TEXTURE_RECTANGLE are supported");
    }
    if (array != (desc.layers > 0)) {
        throw std::invalid_argument(describe("Texture", desc.label ? desc.label : "") +
                                    ": layers must be given for (and only for) an array");
    }
    mLayers = desc.layers;
    GLuint id = 0;
    glCreateTextures(desc.target, 1, &id);
    mHandle = Handle<Deleter>(id);
    if (array) {
        glTextureStorage3D(id, std::max(desc.levels, 1), desc.format, desc.width, desc.height,
                           desc.layers);
    } else {
        glTextureStorage2D(id, std::max(desc.levels, 1), desc.format, desc.width, desc.height);
    }
    // Rectangle textures reject mipmap filters and repeat wraps; leave their defaults alone.
    if (desc.target != GL_TEXTURE_RECTANGLE) {
        glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(desc.minFilter));
        glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, static_cast<GLint>(desc.magFilter));
        glTextureParameteri(id, GL_TEXTURE_WRAP_S, static_cast<GLint>(desc.wrap));
        glTextureParameteri(id, GL_TEXTURE_WRAP_T, static_cast<GLint>(desc.wrap));
    } else {
        glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, static_cast<GLint>(desc.magFilter));
    }
    label(GL_TEXTURE, id, desc.label);
}

void BufferTexture::upload(const void* data, std::size_t bytes, GLenum format,
                           std::size_t texelBytes, const char* label) {
    GLint maxTexels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
    if (texelBytes == 0 || bytes / texelBytes > static_cast<std::size_t>(maxTexels))
        throw GlError(describe("BufferTexture", label ? label : "") + ": " +
                      std::to_string(texelBytes ? bytes / texelBytes : 0) +
                      " texels, more than GL_MAX_TEXTURE_BUFFER_SIZE = " +
                      std::to_string(maxTexels));
    const std::vector<std::byte> zero(texelBytes);
    mBuffer = Buffer({.size = bytes ? bytes : texelBytes,
                      .data = bytes ? data : zero.data(),
                      .flags = 0,
                      .label = label});
    if (!mTexture) {
        GLuint id = 0;
        glCreateTextures(GL_TEXTURE_BUFFER, 1, &id);
        mTexture = Handle<Deleter>(id);
    }
    glTextureBuffer(mTexture.id(), format, mBuffer.id());
}

void Texture::read(GLenum format, GLenum type, std::vector<std::byte>& out) const {
    if (mLayers > 0) throw std::logic_error("Texture::read: not for array textures");
    std::size_t bpp = pixelBytes(format, type);
    if (bpp == 0) throw std::invalid_argument("Texture::read: unsupported format/type pair");
    std::size_t bytes = bpp * static_cast<std::size_t>(mWidth) * static_cast<std::size_t>(mHeight);
    out.resize(bytes);
    PackStateGuard guard;
    glGetTextureImage(mHandle.id(), 0, format, type, static_cast<GLsizei>(bytes), out.data());
}

std::vector<float> Texture::readFloat(int channels) const {
    static constexpr GLenum kFormats[] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};
    if (channels < 1 || channels > 4) {
        throw std::invalid_argument("Texture::readFloat: channels must be 1..4");
    }
    if (mLayers > 0) throw std::logic_error("Texture::readFloat: not for array textures");
    std::vector<float> out(static_cast<std::size_t>(mWidth) * static_cast<std::size_t>(mHeight) *
                           static_cast<std::size_t>(channels));
    PackStateGuard guard;
    glGetTextureImage(mHandle.id(), 0, kFormats[channels - 1], GL_FLOAT,
                      static_cast<GLsizei>(out.size() * sizeof(float)), out.data());
    return out;
}

// ---------------------------------------------------------------------------------------------
// Framebuffer

Framebuffer::Framebuffer(const FramebufferDesc& desc) {
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    mHandle = Handle<Deleter>(id);
    label(GL_FRAMEBUFFER, id, desc.label);

    std::vector<GLenum> colors;
    for (const FramebufferAttachment& a : desc.attachments) {
        if (!a.texture) {
            throw std::invalid_argument(describe("Framebuffer", desc.label ? desc.label : "") +
                                        ": attachment without a texture");
        }
        if (a.layer >= 0) {
            glNamedFramebufferTextureLayer(id, a.attachment, a.texture->id(), a.level, a.layer);
        } else {
            glNamedFramebufferTexture(id, a.attachment, a.texture->id(), a.level);
        }
        if (isColorAttachment(a.attachment)) colors.push_back(a.attachment);
    }
    setDrawBuffers(colors);
    // Depth-only targets (shadow maps, stencil passes) read nothing either.
    glNamedFramebufferReadBuffer(id, colors.empty() ? GL_NONE : colors.front());

    GLenum status = glCheckNamedFramebufferStatus(id, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        throw GlError(describe("Framebuffer", desc.label ? desc.label : "") +
                      " is incomplete: " + framebufferStatusName(status));
    }
}

void Framebuffer::setDrawBuffers(std::span<const GLenum> buffers) {
    if (buffers.empty()) {
        glNamedFramebufferDrawBuffer(mHandle.id(), GL_NONE);
    } else {
        glNamedFramebufferDrawBuffers(mHandle.id(), static_cast<GLsizei>(buffers.size()),
                                      buffers.data());
    }
}

// ---------------------------------------------------------------------------------------------
// VertexArray

VertexArray::VertexArray(const char* text) {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    mHandle = Handle<Deleter>(id);
    label(GL_VERTEX_ARRAY, id, text);
}

void VertexArray::attribute(GLuint index, GLuint binding, int components, GLenum type,
                            GLuint relativeOffset) {
    GLuint id = mHandle.id();
    glEnableVertexArrayAttrib(id, index);
    switch (type) {
    // Integer types feed integer shader inputs (ivec/uvec: ids, packed edge data) unconverted;
    // normalised or float-converted integers are not needed by any pass.
    case GL_BYTE:
    case GL_UNSIGNED_BYTE:
    case GL_SHORT:
    case GL_UNSIGNED_SHORT:
    case GL_INT:
    case GL_UNSIGNED_INT:
        glVertexArrayAttribIFormat(id, index, components, type, relativeOffset);
        break;
    default:
        glVertexArrayAttribFormat(id, index, components, type, GL_FALSE, relativeOffset);
        break;
    }
    glVertexArrayAttribBinding(id, index, binding);
}

void VertexArray::vertexBuffer(GLuint binding, const Buffer& buffer, GLintptr offset,
                               GLsizei stride) {
    glVertexArrayVertexBuffer(mHandle.id(), binding, buffer.id(), offset, stride);
}

void VertexArray::elementBuffer(const Buffer& buffer) {
    glVertexArrayElementBuffer(mHandle.id(), buffer.id());
}

// ---------------------------------------------------------------------------------------------

GLint Program::uniformLocation(const char* name) const {
    return glGetUniformLocation(mHandle.id(), name);
}

Query::Query(GLenum target) {
    GLuint id = 0;
    glCreateQueries(target, 1, &id);
    mHandle = Handle<Deleter>(id);
}

} // namespace gpu
