// Move-only RAII owners of GL object names, after Magnum's GL::Buffer: copy is
// deleted, move is noexcept, NoCreate makes an empty object without touching GL (so members
// can be declared before a context exists), wrap()/release() hand names in and out for
// interop. A moved-from object owns nothing; destroying an empty object calls no GL.
#pragma once

#include "gpu/gl.h"

#include <utility>

namespace veil::gpu {

struct NoCreateT {
    explicit constexpr NoCreateT() = default;
};
inline constexpr NoCreateT NoCreate{};

// Traits: static void destroy(GLuint).
template <typename Traits>
class GlObject {
public:
    explicit GlObject(NoCreateT) noexcept {}
    GlObject(const GlObject&) = delete;
    GlObject& operator=(const GlObject&) = delete;
    GlObject(GlObject&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
    GlObject& operator=(GlObject&& other) noexcept {
        // The old name moves into `other` and is deleted with it.
        std::swap(id_, other.id_);
        return *this;
    }
    ~GlObject() {
        if (id_) Traits::destroy(id_);
    }

    GLuint id() const noexcept { return id_; }
    explicit operator bool() const noexcept { return id_ != 0; }
    // Gives up ownership; the caller must delete the name.
    GLuint release() noexcept { return std::exchange(id_, 0); }

protected:
    explicit GlObject(GLuint id) noexcept : id_(id) {}
    GLuint id_ = 0;
};

} // namespace veil::gpu
