// Reading textures back to the CPU (tests, image output).
#pragma once

#include "base/image.h"
#include "gpu/objects.h"

#include <vector>

namespace veil::gpu {

using veil::ImageF;

// Reads level 0 of a 2D texture as float RGBA (channels = 4) or R (channels = 1), flipped so
// that row 0 is the top of the image.
ImageF readTexture(const Texture& texture, int channels = 4);

// The same into a caller's buffer of width * height * channels floats (the texture's size),
// with no copy on the CPU side: the driver writes into `pixels`, then rows are flipped in place.
void readTextureInto(const Texture& texture, int channels, float* pixels, std::size_t count);

} // namespace veil::gpu
