// The opaque casters' depth maps of every light view, one layer of a DEPTH32F texture array
// each [Williams78], storing the normalized linear depth along the view's axis
// (shaders/shadows/common/depth.frag). Every shadow technique has one: `opaque` is just this,
// the others add the transparent casters and the fog on top. Receivers sample it through
// shaders/shadows/common/opaque_depth.glsl at VEIL_TEX_SHADOW_MAP.
#pragma once

#include "shadows/technique.h"

namespace veil::shadows {

class DepthMaps {
public:
    explicit DepthMaps(gpu::ProgramManager& programs);
    void resize(int size, int layers);
    // Clears every layer and draws the opaque casters into it.
    void render(const pass::Context& frame) { renderRows(frame, 0, size_); }
    // The same restricted to the texel rows [y0, y1) of every layer (pass::Pass::executeRows):
    // the clear and the draws scissored to the band.
    void renderRows(const pass::Context& frame, int y0, int y1);
    void bind() const { texture_.bind(VEIL_TEX_SHADOW_MAP); }
    const gpu::Texture& texture() const { return texture_; }
    std::size_t gpuBytes() const { return std::size_t(size_) * size_ * layers_ * 4; }
    int size() const { return size_; }
    int layers() const { return layers_; }

private:
    gpu::ProgramManager& programs_;
    gpu::ProgramHandle program_;
    gpu::Texture texture_{gpu::NoCreate};
    gpu::Framebuffer framebuffer_{gpu::NoCreate};
    int size_ = 0, layers_ = 0;
};

// Sets the uniforms of frame/mesh.vert for drawing casters into `view` (its matrix, and
// particles facing the light).
void setCasterView(const gpu::Program& program, const LightView& view);

} // namespace veil::shadows
