#include "gpu/readback.h"

#include "base/error.h"

#include <algorithm>

namespace veil::gpu {

ImageF readTexture(const Texture& texture, int channels) {
    ImageF image;
    image.width = texture.width();
    image.height = texture.height();
    image.channels = channels;
    image.pixels.resize(static_cast<std::size_t>(image.width) * image.height * channels);
    readTextureInto(texture, channels, image.pixels.data(), image.pixels.size());
    return image;
}

void readTextureInto(const Texture& texture, int channels, float* pixels, std::size_t count) {
    VEIL_CHECK(channels == 1 || channels == 4, "readTexture: {} channels unsupported", channels);
    const std::size_t row = static_cast<std::size_t>(texture.width()) * channels;
    const int height = texture.height();
    VEIL_CHECK(count == row * height, "readTexture: buffer of {} floats for a {}x{}x{} texture",
               count, texture.width(), height, channels);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(texture.id(), 0, channels == 4 ? GL_RGBA : GL_RED, GL_FLOAT,
                      static_cast<GLsizei>(count * sizeof(float)), pixels);
    // GL's row 0 is the bottom; images are stored top-down.
    for (int y = 0; y < height / 2; ++y)
        std::swap_ranges(pixels + y * row, pixels + (y + 1) * row, pixels + (height - 1 - y) * row);
}

} // namespace veil::gpu
