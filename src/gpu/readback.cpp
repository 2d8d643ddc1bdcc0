#include "gpu/readback.h"

#include "base/error.h"

#include <algorithm>

namespace veil::gpu {

ImageF readTexture(const Texture& texture, int channels) {
    VEIL_CHECK(channels == 1 || channels == 4, "readTexture: {} channels unsupported", channels);
    ImageF image;
    image.width = texture.width();
    image.height = texture.height();
    image.channels = channels;
    const std::size_t row = static_cast<std::size_t>(image.width) * channels;
    image.pixels.resize(row * image.height);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(texture.id(), 0, channels == 4 ? GL_RGBA : GL_RED, GL_FLOAT,
                      static_cast<GLsizei>(image.pixels.size() * sizeof(float)),
                      image.pixels.data());
    // GL's row 0 is the bottom; images are stored top-down.
    for (int y = 0; y < image.height / 2; ++y)
        std::swap_ranges(image.pixels.begin() + y * row, image.pixels.begin() + (y + 1) * row,
                         image.pixels.begin() + (image.height - 1 - y) * row);
    return image;
}

} // namespace veil::gpu
