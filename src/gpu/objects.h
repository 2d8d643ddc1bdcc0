// GL object types: Buffer, Texture, Sampler, Framebuffer, VertexArray, Query.
// All use direct state access (GL 4.5), so creating or editing one does not disturb bindings.
#pragma once

#include "gpu/gl_object.h"

#include <cstddef>
#include <initializer_list>
#include <span>

namespace veil::gpu {

struct BufferTraits {
    static void destroy(GLuint id) { glDeleteBuffers(1, &id); }
};
class Buffer : public GlObject<BufferTraits> {
public:
    using GlObject::GlObject;
    Buffer(); // glCreateBuffers
    static Buffer wrap(GLuint id) { return Buffer(id); }

    // Immutable storage (glNamedBufferStorage). data may be null.
    void setStorage(std::size_t bytes, const void* data, GLbitfield flags = GL_DYNAMIC_STORAGE_BIT);
    template <typename T>
    void setStorage(std::span<const T> data, GLbitfield flags = GL_DYNAMIC_STORAGE_BIT) {
        setStorage(data.size_bytes(), data.data(), flags);
    }
    void setSubData(std::size_t offset, std::size_t bytes, const void* data);
    void bindBase(GLenum target, GLuint index) const { glBindBufferBase(target, index, id_); }
    std::size_t size() const { return size_; }

private:
    explicit Buffer(GLuint id) : GlObject(id) {}
    std::size_t size_ = 0;
};

struct TextureTraits {
    static void destroy(GLuint id) { glDeleteTextures(1, &id); }
};
class Texture : public GlObject<TextureTraits> {
public:
    using GlObject::GlObject;
    explicit Texture(GLenum target); // glCreateTextures
    static Texture wrap(GLenum target, GLuint id) { return Texture(target, id); }

    Texture& storage2D(GLsizei levels, GLenum internalFormat, GLsizei width, GLsizei height);
    Texture& storage2DMultisample(GLsizei samples, GLenum internalFormat, GLsizei width,
                                  GLsizei height);
    Texture& storage3D(GLsizei levels, GLenum internalFormat, GLsizei width, GLsizei height,
                       GLsizei depth);
    Texture& parameter(GLenum name, GLint value);
    Texture& parameter(GLenum name, GLfloat value);
    void bind(GLuint unit) const { glBindTextureUnit(unit, id_); }

    GLenum target() const { return target_; }
    GLenum format() const { return format_; }
    GLsizei width() const { return width_; }
    GLsizei height() const { return height_; }
    GLsizei depth() const { return depth_; }

private:
    Texture(GLenum target, GLuint id) : GlObject(id), target_(target) {}
    GLenum target_ = 0;
    GLenum format_ = 0;
    GLsizei width_ = 0, height_ = 0, depth_ = 0;
};

struct SamplerTraits {
    static void destroy(GLuint id) { glDeleteSamplers(1, &id); }
};
class Sampler : public GlObject<SamplerTraits> {
public:
    using GlObject::GlObject;
    Sampler();
    Sampler& parameter(GLenum name, GLint value);
    Sampler& parameter(GLenum name, GLfloat value);
    void bind(GLuint unit) const { glBindSampler(unit, id_); }
};

struct FramebufferTraits {
    static void destroy(GLuint id) { glDeleteFramebuffers(1, &id); }
};
class Framebuffer : public GlObject<FramebufferTraits> {
public:
    using GlObject::GlObject;
    Framebuffer();
    Framebuffer& attach(GLenum attachment, const Texture& texture, GLint level = 0);
    // One layer of an array (or 3D, cube) texture.
    Framebuffer& attachLayer(GLenum attachment, const Texture& texture, GLint layer,
                             GLint level = 0);
    // Sets the draw buffers (GL_COLOR_ATTACHMENTi or GL_NONE).
    Framebuffer& drawBuffers(std::initializer_list<GLenum> buffers);
    // Throws veil::Error naming the incompleteness status.
    void checkComplete(const char* what) const;
    void bind() const { glBindFramebuffer(GL_FRAMEBUFFER, id_); }
};

struct VertexArrayTraits {
    static void destroy(GLuint id) { glDeleteVertexArrays(1, &id); }
};
class VertexArray : public GlObject<VertexArrayTraits> {
public:
    using GlObject::GlObject;
    VertexArray();
    // Float attribute `location` with `components` floats read from `buffer` at `binding`.
    VertexArray& attribute(GLuint location, GLuint binding, const Buffer& buffer, GLint components,
                           GLsizei stride, GLuint offset = 0);
    VertexArray& indexBuffer(const Buffer& buffer);
    void bind() const { glBindVertexArray(id_); }
};

struct QueryTraits {
    static void destroy(GLuint id) { glDeleteQueries(1, &id); }
};
class Query : public GlObject<QueryTraits> {
public:
    using GlObject::GlObject;
    explicit Query(GLenum target);
    GLenum target() const { return target_; }
    bool resultAvailable() const;
    GLuint64 result() const; // waits

private:
    GLenum target_ = 0;
};

} // namespace veil::gpu
