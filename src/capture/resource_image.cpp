#include "capture/resource_image.h"

#include "base/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>

namespace veil::capture {

namespace {

bool isDepth(GLenum f) {
    return f == GL_DEPTH_COMPONENT32F || f == GL_DEPTH_COMPONENT24 || f == GL_DEPTH_COMPONENT16;
}
bool isSingleChannel(GLenum f) { return f == GL_R16F || f == GL_R32F || f == GL_R8; }
bool isInteger(GLenum f) { return f == GL_R32UI || f == GL_RGBA32UI; }
// Colour formats read back as RGBA floats (two-channel ones with B = 0, A = 1).
bool isColour(GLenum f) {
    return f == GL_RGBA8 || f == GL_RGBA16F || f == GL_RGBA32F || f == GL_RG32F || f == GL_RG16F ||
           f == GL_RG16 || f == GL_RGBA16 || f == GL_RGBA16_SNORM;
}

} // namespace

std::string formatName(GLenum format) {
    switch (format) {
    case GL_RGBA8:
        return "GL_RGBA8";
    case GL_RGBA16F:
        return "GL_RGBA16F";
    case GL_RGBA32F:
        return "GL_RGBA32F";
    case GL_RG32F:
        return "GL_RG32F";
    case GL_RG16F:
        return "GL_RG16F";
    case GL_RG16:
        return "GL_RG16";
    case GL_RGBA16:
        return "GL_RGBA16";
    case GL_RGBA16_SNORM:
        return "GL_RGBA16_SNORM";
    case GL_R16F:
        return "GL_R16F";
    case GL_R32F:
        return "GL_R32F";
    case GL_R8:
        return "GL_R8";
    case GL_R32UI:
        return "GL_R32UI";
    case GL_RGBA32UI:
        return "GL_RGBA32UI";
    case GL_DEPTH_COMPONENT32F:
        return "GL_DEPTH_COMPONENT32F";
    case GL_DEPTH_COMPONENT24:
        return "GL_DEPTH_COMPONENT24";
    case GL_DEPTH_COMPONENT16:
        return "GL_DEPTH_COMPONENT16";
    default:
        return fmt::format("0x{:04x}", format);
    }
}

std::size_t bytesPerTexel(GLenum format) {
    switch (format) {
    case GL_RGBA8:
    case GL_R32F:
    case GL_R32UI:
    case GL_DEPTH_COMPONENT32F:
    case GL_DEPTH_COMPONENT24:
        return 4;
    case GL_RGBA16F:
    case GL_RG32F:
    case GL_RGBA16:
    case GL_RGBA16_SNORM:
        return 8;
    case GL_RG16F:
    case GL_RG16:
        return 4;
    case GL_RGBA32F:
    case GL_RGBA32UI:
        return 16;
    case GL_R16F:
    case GL_DEPTH_COMPONENT16:
        return 2;
    case GL_R8:
        return 1;
    default:
        return 0;
    }
}

int resourceLayers(const gpu::Texture& t) {
    return t.target() == GL_TEXTURE_2D ? 1 : std::max(1, t.depth());
}

std::string whyNotReadable(const gpu::Texture& t) {
    if (!t) return "no texture";
    const GLenum target = t.target();
    if (target != GL_TEXTURE_2D && target != GL_TEXTURE_2D_ARRAY && target != GL_TEXTURE_3D)
        return fmt::format("texture target 0x{:04x} (e.g. multisample) cannot be read back",
                           target);
    const GLenum f = t.format();
    if (!isDepth(f) && !isSingleChannel(f) && !isInteger(f) && !isColour(f))
        return "format " + formatName(f) + " is not shown";
    return {};
}

ResourceImage readResourceImage(const gpu::Texture& t, int layer) {
    const std::string why = whyNotReadable(t);
    VEIL_CHECK(why.empty(), "resource texture: {}", why);
    const GLenum f = t.format();
    const int layers = resourceLayers(t);
    VEIL_CHECK(layer >= 0 && layer < layers, "layer {} out of range 0..{}", layer, layers - 1);
    ResourceImage img;
    img.width = t.width();
    img.height = t.height();
    img.depth = isDepth(f);
    const std::size_t texels = std::size_t(img.width) * img.height;
    std::vector<float> raw;
    int channels = 4;
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    const GLint z = t.target() == GL_TEXTURE_2D ? 0 : layer;
    if (isInteger(f)) {
        const int words = f == GL_RGBA32UI ? 4 : 1;
        std::vector<GLuint> u(texels * words);
        glGetTextureSubImage(t.id(), 0, 0, 0, z, img.width, img.height, 1,
                             words == 4 ? GL_RGBA_INTEGER : GL_RED_INTEGER, GL_UNSIGNED_INT,
                             static_cast<GLsizei>(u.size() * sizeof(GLuint)), u.data());
        channels = 1;
        raw.resize(texels);
        for (std::size_t i = 0; i < texels; ++i) {
            int bits = 0;
            for (int w = 0; w < words; ++w)
                bits += std::popcount(u[i * words + w]);
            raw[i] = static_cast<float>(bits);
        }
        img.channels = {"Y"};
    } else {
        GLenum format = GL_RGBA;
        if (isDepth(f) || isSingleChannel(f)) {
            channels = 1;
            format = isDepth(f) ? GL_DEPTH_COMPONENT : GL_RED;
            img.channels = {isDepth(f) ? "Z" : "Y"};
        } else {
            img.channels = {"R", "G", "B", "A"};
        }
        raw.resize(texels * channels);
        glGetTextureSubImage(t.id(), 0, 0, 0, z, img.width, img.height, 1, format, GL_FLOAT,
                             static_cast<GLsizei>(raw.size() * sizeof(float)), raw.data());
    }
    // GL's row 0 is the bottom.
    const std::size_t row = std::size_t(img.width) * channels;
    img.pixels.resize(raw.size());
    for (int y = 0; y < img.height; ++y)
        std::copy_n(raw.begin() + (img.height - 1 - y) * row, row, img.pixels.begin() + y * row);
    return img;
}

} // namespace veil::capture
