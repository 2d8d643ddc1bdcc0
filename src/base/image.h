// A float image on the CPU: row 0 is the top row, channels interleaved.
#pragma once

#include <cstddef>
#include <vector>

namespace veil {

struct ImageF {
    int width = 0, height = 0, channels = 0;
    std::vector<float> pixels;

    ImageF() = default;
    ImageF(int w, int h, int c)
        : width(w), height(h), channels(c), pixels(static_cast<std::size_t>(w) * h * c, 0.0f) {}
    std::size_t index(int x, int y, int c) const {
        return (static_cast<std::size_t>(y) * width + x) * channels + c;
    }
    float at(int x, int y, int c) const { return pixels[index(x, y, c)]; }
    float& at(int x, int y, int c) { return pixels[index(x, y, c)]; }
};

} // namespace veil
