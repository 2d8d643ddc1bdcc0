// One 2D image of a frame resource's texture, read back as floats: a 2D texture, one layer
// of a 2D array (a shadow technique's maps: one layer per light view) or one z slice of a 3D
// texture (the fog's light transmittance). `veil render --dump` writes these; the viewer's
// debug views show them and its EXR screenshot of a debug view writes them, so both carry the
// same values.
#pragma once

#include "gpu/objects.h"

#include <string>
#include <vector>

namespace veil::capture {

struct ResourceImage {
    int width = 0, height = 0;
    std::vector<std::string> channels; // {"Z"} depth, {"Y"} one channel, {"R","G","B","A"}
    std::vector<float> pixels;         // interleaved, row 0 = top
    bool depth = false;                // a depth format (window depth, 1 = nothing drawn)
};

// "GL_RGBA16F", ... for manifests and the panel.
std::string formatName(GLenum format);
// Bytes per texel of the formats frame resources use (0 when unknown).
std::size_t bytesPerTexel(GLenum format);
// Layers of an array texture or slices of a 3D one (1 for 2D).
int resourceLayers(const gpu::Texture& t);

// Why `t` cannot be shown as an image ("" when it can): multisample textures, other targets.
std::string whyNotReadable(const gpu::Texture& t);

// Reads layer (array) or slice (3D) `layer` of level 0. Integer textures (R32UI, RGBA32UI
// bit words, e.g. slice maps) read as the number of set bits per texel ("Y").
// Throws veil::Error when whyNotReadable() is not empty.
ResourceImage readResourceImage(const gpu::Texture& t, int layer = 0);

} // namespace veil::capture
