// A texture's texels as stored (bits, not values) for bit-exact comparisons of GL results, e.g.
// a refined frame against the frame in one piece.
#pragma once

#include "gpu/objects.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace veil::test {

// Level 0, every layer or slice, `channels` of `format` per texel as `type` (T's size).
template <class T>
std::vector<T> texelBits(const gpu::Texture& t, GLenum format, GLenum type, int channels) {
    std::vector<T> v(std::size_t(t.width()) * t.height() * std::max(1, t.depth()) *
                     std::size_t(channels));
    glGetTextureImage(t.id(), 0, format, type, GLsizei(v.size() * sizeof(T)), v.data());
    return v;
}

inline std::vector<std::uint8_t> rgba8(const gpu::Texture& t) {
    return texelBits<std::uint8_t>(t, GL_RGBA, GL_UNSIGNED_BYTE, 4);
}

// Where two such vectors differ (a size mismatch counts every element of the longer).
template <class T>
std::size_t differing(const std::vector<T>& a, const std::vector<T>& b) {
    if (a.size() != b.size()) return std::max(a.size(), b.size());
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        n += a[i] != b[i];
    return n;
}

} // namespace veil::test
