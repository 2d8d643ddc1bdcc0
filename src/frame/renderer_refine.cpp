// The tiled progressive refinement of frame::Renderer (renderer.h, beginRefinement): the
// per-frame passes once, then the per-pixel passes one screen tile (and a margin) per call.
#include "frame/renderer.h"

#include "base/error.h"

#include <algorithm>

namespace veil::frame {

namespace {
void copyRect(const gpu::Texture& from, const gpu::Texture& to, glm::ivec4 r) {
    glCopyImageSubData(from.id(), GL_TEXTURE_2D, 0, r.x, r.y, 0, to.id(), GL_TEXTURE_2D, 0, r.x,
                       r.y, 0, r.z - r.x, r.w - r.y, 1);
}
gpu::Texture likeTexture(const gpu::Texture& t, GLenum format) {
    gpu::Texture copy(GL_TEXTURE_2D);
    copy.storage2D(1, format, t.width(), t.height());
    return copy;
}
} // namespace

void Renderer::beginRefinement(int tilePx) {
    VEIL_CHECK(tilePx > 0, "refinement tile size {} is not positive", tilePx);
    refine_ = {};
    refine_.tilePx = tilePx;
    refine_.columns = (width_ + tilePx - 1) / tilePx;
    refine_.tiles = refine_.columns * ((height_ + tilePx - 1) / tilePx);
    // The per-frame passes, once: shadow maps, the AO, the opaque image and depth. The fog's
    // light transmittance volumes (march() step 1) follow in slabs, one per refineStep().
    beginFrame();
    runPasses(0, firstPerPixelPass_);
    if (!opaqueHdr_ || opaqueHdr_.width() != width_ || opaqueHdr_.height() != height_) {
        opaqueHdr_ = likeTexture(hdr_, GL_RGBA16F);
        refinedHdr_ = likeTexture(hdr_, GL_RGBA16F);
        refinedLdr_ = likeTexture(ldr_, GL_RGBA8);
    }
    copyRect(hdr_, opaqueHdr_, glm::ivec4(0, 0, width_, height_));
    refine_.active = true;
    passTimes_ = timer_.collect();
}

bool Renderer::refineStep() {
    if (!refine_.active) return true;
    bindFrameState();
    bool slab = false;
    if (fog_) {
        // While the light transmittance volumes are not valid: their next slab, alone.
        gpu::TimerScope timer(timer_, "fog.light_transmittance");
        if (shadowSet_.viewCount > 0) shadows_->bindForReceivers();
        slab = fog_->updateLightVolumesSlab(fogTargets_, kRefineLightSlabTexels);
    }
    if (slab) {
        refine_.lastStep = Refinement::Step::LightSlab;
        ++refine_.lightSlabs;
        passTimes_ = timer_.collect();
        return false;
    }
    refine_.lastStep = Refinement::Step::Tile;
    const int t = refine_.tilePx;
    const int index = refine_.done;
    const int x0 = (index % refine_.columns) * t, y0 = (index / refine_.columns) * t;
    const glm::ivec4 tile(x0, y0, std::min(width_, x0 + t), std::min(height_, y0 + t));
    // The per-pixel passes over the tile and a margin (kRefineMarginPx): a pixel's result in
    // them depends on its own pixel and neighbours within the margin only (the fog's
    // bilateral upsampling), so the tile comes out as in the whole frame.
    const glm::ivec4 r(std::max(0, tile.x - kRefineMarginPx), std::max(0, tile.y - kRefineMarginPx),
                       std::min(width_, tile.z + kRefineMarginPx),
                       std::min(height_, tile.w + kRefineMarginPx));
    // The resolve composites over the whole hdr target (the techniques' resolves are compute
    // over the frame): it starts from the opaque image every tile.
    copyRect(opaqueHdr_, hdr_, r);
    region_ = r;
    fogTargets_.region = r;
    state_.setScissorLimit(glm::ivec4(r.x, r.y, r.z - r.x, r.w - r.y));
    runPasses(firstPerPixelPass_, passes_.passes().size());
    state_.setScissorLimit(std::nullopt);
    state_.apply(gpu::PipelineState{}); // the scissor test off again for whoever draws next
    region_ = glm::ivec4(0, 0, width_, height_);
    fogTargets_.region = glm::ivec4(0);
    copyRect(hdr_, refinedHdr_, tile);
    copyRect(ldr_, refinedLdr_, tile);
    refine_.lastRegion = r;
    ++refine_.done;
    passTimes_ = timer_.collect();
    if (refine_.done < refine_.tiles) return false;
    // Complete: the frame targets hold the frame, as after render().
    copyRect(refinedHdr_, hdr_, glm::ivec4(0, 0, width_, height_));
    copyRect(refinedLdr_, ldr_, glm::ivec4(0, 0, width_, height_));
    refine_.active = false;
    return true;
}

} // namespace veil::frame
