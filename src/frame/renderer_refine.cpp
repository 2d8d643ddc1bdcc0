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

int Renderer::refineMarginPx() const { return oit_->refineMarginPx(); }

void Renderer::beginRefinement(int tilePx) {
    VEIL_CHECK(tilePx > 0, "refinement tile size {} is not positive", tilePx);
    refine_ = {};
    refine_.tilePx = tilePx;
    refine_.columns = (width_ + tilePx - 1) / tilePx;
    const int rows = (height_ + tilePx - 1) / tilePx;
    refine_.tiles = refine_.columns * rows;
    refine_.pixels = static_cast<long long>(width_) * height_;
    refine_.pending.reserve(static_cast<std::size_t>(refine_.tiles) + 8);
    for (int i = refine_.tiles - 1; i >= 0; --i) { // the first tile last: next
        const int x0 = (i % refine_.columns) * tilePx, y0 = (i / refine_.columns) * tilePx;
        refine_.pending.emplace_back(x0, y0, std::min(width_, x0 + tilePx),
                                     std::min(height_, y0 + tilePx));
    }
    // The per-frame passes, once: shadow maps, the AO, the opaque image and depth. The fog's
    // light transmittance volumes (march() step 1) follow in slabs, one per refineStep().
    beginFrame();
    refine_.active = true;
    const std::vector<pass::Pass>& passes = passes_.passes();
    const bool banded = std::any_of(passes.begin(), passes.end(), [](const pass::Pass& p) {
        return p.scope == pass::Scope::Lights && p.executeRows;
    });
    if (!skipShadowPasses_ && banded) {
        // The shadow maps in bands over the next steps (kRefineShadowBandTexels).
        shadowMapsValid_ = false; // until the last band of the last pass
        refine_.shadowPass = 0;
        refine_.perFramePending = true;
    } else {
        runPerFramePasses(true);
    }
    passTimes_ = timer_.collect();
}

void Renderer::runPerFramePasses(bool lights) {
    if (lights) runLightPasses();
    runPasses(pass::Scope::Frame);
    if (!opaqueHdr_ || opaqueHdr_.width() != width_ || opaqueHdr_.height() != height_) {
        opaqueHdr_ = likeTexture(hdr_, GL_RGBA16F);
        refinedHdr_ = likeTexture(hdr_, GL_RGBA16F);
        refinedLdr_ = likeTexture(ldr_, GL_RGBA8);
    }
    copyRect(hdr_, opaqueHdr_, glm::ivec4(0, 0, width_, height_));
    refine_.perFramePending = false;
}

void Renderer::refineShadowStep() {
    // The Lights passes are the first of the list.
    const std::vector<pass::Pass>& passes = passes_.passes();
    const auto i = static_cast<std::size_t>(refine_.shadowPass);
    const int size = shadowMapSize_;
    {
        gpu::TimerScope timer(timer_, passes[i].name);
        if (passes[i].executeRows) {
            // One band of rows (pass::Pass::executeRows: the bands in order equal the
            // pass in one piece), about kRefineShadowBandTexels texels per layer.
            const int rows = std::max(1, kRefineShadowBandTexels / std::max(1, size));
            const int y0 = refine_.shadowRow, y1 = std::min(size, y0 + rows);
            passes[i].executeRows(pass_, y0, y1);
            refine_.shadowRow = y1;
        } else {
            passes[i].execute(pass_);
            refine_.shadowRow = size;
        }
    }
    ++refine_.shadowSteps;
    if (refine_.shadowRow < size) return;
    refine_.shadowRow = 0;
    if (i + 1 < passes.size() && passes[i + 1].scope == pass::Scope::Lights) {
        ++refine_.shadowPass;
        return;
    }
    refine_.shadowPass = -1;
    shadowMapsValid_ = true;
    ++shadowMapRenders_;
}

namespace {
// Halves `t` in each side over maxPx until it fits; the parts not taken go onto `pending` so
// that they come next, in rows from the top left.
glm::ivec4 takeTile(std::vector<glm::ivec4>& pending, int maxPx) {
    glm::ivec4 t = pending.back();
    pending.pop_back();
    while (maxPx > 0 && (t.z - t.x > maxPx || t.w - t.y > maxPx)) {
        const int w = t.z - t.x, h = t.w - t.y;
        const int xm = w > maxPx ? t.x + (w + 1) / 2 : t.z;
        const int ym = h > maxPx ? t.y + (h + 1) / 2 : t.w;
        // Quadrants (or halves) pushed last first: top-left, top-right, bottom-left, bottom-right.
        if (ym < t.w && xm < t.z) pending.emplace_back(xm, ym, t.z, t.w);
        if (ym < t.w) pending.emplace_back(t.x, ym, xm, t.w);
        if (xm < t.z) pending.emplace_back(xm, t.y, t.z, ym);
        t = glm::ivec4(t.x, t.y, xm, ym);
    }
    return t;
}
} // namespace

bool Renderer::refineStep(int maxTilePx) {
    if (!refine_.active) return true;
    bindFrameState();
    if (refine_.shadowPass >= 0) {
        refine_.lastStep = Refinement::Step::ShadowBand;
        refineShadowStep();
        passTimes_ = timer_.collect();
        return false;
    }
    if (refine_.perFramePending) { // the passes after the shadow maps: AO, opaque
        refine_.lastStep = Refinement::Step::PerFrame;
        runPerFramePasses(false);
        passTimes_ = timer_.collect();
        return false;
    }
    // The per-frame work of the Pixels passes (the fog's light transmittance volumes) while
    // there is some: its next step, alone.
    bool slab = false;
    for (const pass::Pass& p : passes_.passes()) {
        if (p.scope != pass::Scope::Pixels || !p.prepareStep) continue;
        gpu::TimerScope timer(timer_, p.prepareName);
        if (p.receivesShadows && shadowSet_.viewCount > 0) shadows_->bindForReceivers();
        if ((slab = p.prepareStep(pass_))) break;
    }
    if (slab) {
        refine_.lastStep = Refinement::Step::LightSlab;
        ++refine_.lightSlabs;
        passTimes_ = timer_.collect();
        return false;
    }
    refine_.lastStep = Refinement::Step::Tile;
    const glm::ivec4 tile = takeTile(refine_.pending, maxTilePx);
    // The per-pixel passes over the tile and the OIT technique's margin (refineMarginPx(): what
    // its resolve reads around a pixel), so the tile comes out as in the whole frame. The fog
    // marches the texels its upsampling reads for these pixels (FogPass::march).
    const int m = refineMarginPx();
    const glm::ivec4 r(std::max(0, tile.x - m), std::max(0, tile.y - m),
                       std::min(width_, tile.z + m), std::min(height_, tile.w + m));
    // The resolve composites over hdr in the region (pass::Context::region): it starts from
    // the opaque image there every tile.
    copyRect(opaqueHdr_, hdr_, r);
    setRegion(r);
    state_.setScissorLimit(glm::ivec4(r.x, r.y, r.z - r.x, r.w - r.y));
    runPasses(pass::Scope::Pixels);
    state_.setScissorLimit(std::nullopt);
    state_.apply(gpu::PipelineState{}); // the scissor test off again for whoever draws next
    setRegion(glm::ivec4(0, 0, width_, height_));
    copyRect(hdr_, refinedHdr_, tile);
    copyRect(ldr_, refinedLdr_, tile);
    refine_.lastTile = tile;
    refine_.lastRegion = r;
    ++refine_.done;
    refine_.pixelsDone += static_cast<long long>(tile.z - tile.x) * (tile.w - tile.y);
    passTimes_ = timer_.collect();
    if (!refine_.pending.empty()) return false;
    // Complete: the frame targets hold the frame, as after render().
    copyRect(refinedHdr_, hdr_, glm::ivec4(0, 0, width_, height_));
    copyRect(refinedLdr_, ldr_, glm::ivec4(0, 0, width_, height_));
    refine_.active = false;
    return true;
}

} // namespace veil::frame
