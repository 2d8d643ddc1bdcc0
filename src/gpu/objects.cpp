#include "gpu/objects.h"

#include "base/error.h"

namespace veil::gpu {

Buffer::Buffer() : GlObject(NoCreate) { glCreateBuffers(1, &id_); }

void Buffer::setStorage(std::size_t bytes, const void* data, GLbitfield flags) {
    VEIL_CHECK(size_ == 0, "buffer {} already has immutable storage", id_);
    // A zero-sized store is legal to ask for but not to create: keep one byte.
    glNamedBufferStorage(id_, static_cast<GLsizeiptr>(bytes ? bytes : 1), data, flags);
    size_ = bytes;
}

void Buffer::setSubData(std::size_t offset, std::size_t bytes, const void* data) {
    VEIL_CHECK(offset + bytes <= size_, "buffer {}: write of {} bytes at {} past its {} bytes", id_,
               bytes, offset, size_);
    glNamedBufferSubData(id_, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
}

Texture::Texture(GLenum target) : GlObject(NoCreate), target_(target) {
    glCreateTextures(target, 1, &id_);
}

Texture& Texture::storage2D(GLsizei levels, GLenum internalFormat, GLsizei width, GLsizei height) {
    glTextureStorage2D(id_, levels, internalFormat, width, height);
    format_ = internalFormat;
    width_ = width;
    height_ = height;
    depth_ = 1;
    return *this;
}

Texture& Texture::storage2DMultisample(GLsizei samples, GLenum internalFormat, GLsizei width,
                                       GLsizei height) {
    glTextureStorage2DMultisample(id_, samples, internalFormat, width, height, GL_TRUE);
    format_ = internalFormat;
    width_ = width;
    height_ = height;
    depth_ = 1;
    return *this;
}

Texture& Texture::storage3D(GLsizei levels, GLenum internalFormat, GLsizei width, GLsizei height,
                            GLsizei depth) {
    glTextureStorage3D(id_, levels, internalFormat, width, height, depth);
    format_ = internalFormat;
    width_ = width;
    height_ = height;
    depth_ = depth;
    return *this;
}

Texture& Texture::parameter(GLenum name, GLint value) {
    glTextureParameteri(id_, name, value);
    return *this;
}
Texture& Texture::parameter(GLenum name, GLfloat value) {
    glTextureParameterf(id_, name, value);
    return *this;
}

Sampler::Sampler() : GlObject(NoCreate) { glCreateSamplers(1, &id_); }
Sampler& Sampler::parameter(GLenum name, GLint value) {
    glSamplerParameteri(id_, name, value);
    return *this;
}
Sampler& Sampler::parameter(GLenum name, GLfloat value) {
    glSamplerParameterf(id_, name, value);
    return *this;
}

Framebuffer::Framebuffer() : GlObject(NoCreate) { glCreateFramebuffers(1, &id_); }

Framebuffer& Framebuffer::attach(GLenum attachment, const Texture& texture, GLint level) {
    glNamedFramebufferTexture(id_, attachment, texture.id(), level);
    return *this;
}

Framebuffer& Framebuffer::attachLayer(GLenum attachment, const Texture& texture, GLint layer,
                                      GLint level) {
    glNamedFramebufferTextureLayer(id_, attachment, texture.id(), level, layer);
    return *this;
}

Framebuffer& Framebuffer::drawBuffers(std::initializer_list<GLenum> buffers) {
    glNamedFramebufferDrawBuffers(id_, static_cast<GLsizei>(buffers.size()), buffers.begin());
    return *this;
}

void Framebuffer::checkComplete(const char* what) const {
    const GLenum status = glCheckNamedFramebufferStatus(id_, GL_FRAMEBUFFER);
    VEIL_CHECK(status == GL_FRAMEBUFFER_COMPLETE, "framebuffer '{}' is incomplete (status 0x{:x})",
               what, status);
}

VertexArray::VertexArray() : GlObject(NoCreate) { glCreateVertexArrays(1, &id_); }

VertexArray& VertexArray::attribute(GLuint location, GLuint binding, const Buffer& buffer,
                                    GLint components, GLsizei stride, GLuint offset) {
    glVertexArrayVertexBuffer(id_, binding, buffer.id(), 0, stride);
    glEnableVertexArrayAttrib(id_, location);
    glVertexArrayAttribFormat(id_, location, components, GL_FLOAT, GL_FALSE, offset);
    glVertexArrayAttribBinding(id_, location, binding);
    return *this;
}

VertexArray& VertexArray::indexBuffer(const Buffer& buffer) {
    glVertexArrayElementBuffer(id_, buffer.id());
    return *this;
}

Query::Query(GLenum target) : GlObject(NoCreate), target_(target) {
    // Mesa (llvmpipe 24) refuses ARB_pipeline_statistics_query targets in glCreateQueries
    // (GL_INVALID_ENUM) although it lists the extension; a generated name becomes a query of
    // its target at its first glBeginQuery, which is all these are used for.
    const bool statistics = (target >= GL_VERTICES_SUBMITTED_ARB && // 0x82EE ... 0x82F7
                             target <= GL_CLIPPING_OUTPUT_PRIMITIVES_ARB) ||
                            target == GL_GEOMETRY_SHADER_INVOCATIONS;
    if (statistics)
        glGenQueries(1, &id_);
    else
        glCreateQueries(target, 1, &id_);
}

bool Query::resultAvailable() const {
    GLint available = 0;
    glGetQueryObjectiv(id_, GL_QUERY_RESULT_AVAILABLE, &available);
    return available != 0;
}

GLuint64 Query::result() const {
    GLuint64 value = 0;
    glGetQueryObjectui64v(id_, GL_QUERY_RESULT, &value);
    return value;
}

} // namespace veil::gpu
