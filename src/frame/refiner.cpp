// The tiled progressive refinement of frame::Renderer (refiner.h): the per-frame passes once,
// then the per-pixel passes one screen tile (and a margin) per call.
#include "frame/refiner.h"

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

void Refiner::begin(int tilePx) {
    VEIL_CHECK(tilePx > 0, "refinement tile size {} is not positive", tilePx);
    const int width = r_.width_, height = r_.height_;
    state_ = {};
    state_.tilePx = tilePx;
    state_.columns = (width + tilePx - 1) / tilePx;
    const int rows = (height + tilePx - 1) / tilePx;
    state_.tiles = state_.columns * rows;
    state_.pixels = static_cast<long long>(width) * height;
    state_.pending.reserve(static_cast<std::size_t>(state_.tiles) + 8);
    for (int i = state_.tiles - 1; i >= 0; --i) { // the first tile last: next
        const int x0 = (i % state_.columns) * tilePx, y0 = (i / state_.columns) * tilePx;
        state_.pending.emplace_back(x0, y0, std::min(width, x0 + tilePx),
                                    std::min(height, y0 + tilePx));
    }
    // The per-frame passes, once: shadow maps, the AO, the opaque image and depth. The fog's
    // light transmittance volumes (march() step 1) follow in slabs, one per refineStep().
    r_.beginFrame();
    state_.active = true;
    const std::vector<pass::Pass>& passes = r_.passes_.passes();
    const bool banded = std::any_of(passes.begin(), passes.end(), [](const pass::Pass& p) {
        return p.scope == pass::Scope::Lights && p.executeRows;
    });
    if (!r_.reuse().skip && banded) {
        // The shadow maps in bands over the next steps (kShadowBandTexels).
        r_.reuse().valid = false; // until the last band of the last pass
        state_.shadowPass = 0;
        state_.perFramePending = true;
    } else {
        runPerFramePasses(true);
    }
    r_.passTimes_ = r_.timer_.collect();
}

void Refiner::runPerFramePasses(bool lights) {
    if (lights) r_.runLightPasses();
    r_.runPasses(pass::Scope::Frame);
    const gpu::Texture &hdr = r_.targets_.hdr, &ldr = r_.targets_.ldr;
    if (!opaqueHdr_ || opaqueHdr_.width() != r_.width_ || opaqueHdr_.height() != r_.height_) {
        opaqueHdr_ = likeTexture(hdr, GL_RGBA16F);
        refinedHdr_ = likeTexture(hdr, GL_RGBA16F);
        refinedLdr_ = likeTexture(ldr, GL_RGBA8);
    }
    copyRect(hdr, opaqueHdr_, glm::ivec4(0, 0, r_.width_, r_.height_));
    state_.perFramePending = false;
}

void Refiner::shadowStep() {
    // The Lights passes are the first of the list.
    const std::vector<pass::Pass>& passes = r_.passes_.passes();
    const auto i = static_cast<std::size_t>(state_.shadowPass);
    const int size = r_.stages_.shadows->mapSize();
    {
        gpu::TimerScope timer(r_.timer_, passes[i].name);
        if (passes[i].executeRows) {
            // One band of rows (pass::Pass::executeRows: the bands in order equal the
            // pass in one piece), about kShadowBandTexels texels per layer.
            const int rows = std::max(1, kShadowBandTexels / std::max(1, size));
            const int y0 = state_.shadowRow, y1 = std::min(size, y0 + rows);
            passes[i].executeRows(r_.pass_, y0, y1);
            state_.shadowRow = y1;
        } else {
            passes[i].execute(r_.pass_);
            state_.shadowRow = size;
        }
    }
    ++state_.shadowSteps;
    if (state_.shadowRow < size) return;
    state_.shadowRow = 0;
    if (i + 1 < passes.size() && passes[i + 1].scope == pass::Scope::Lights) {
        ++state_.shadowPass;
        return;
    }
    state_.shadowPass = -1;
    r_.reuse().valid = true;
    ++r_.reuse().renders;
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

bool Refiner::step(int maxTilePx) {
    if (!state_.active) return true;
    r_.bindFrameState();
    if (state_.shadowPass >= 0) {
        state_.lastStep = Refinement::Step::ShadowBand;
        shadowStep();
        r_.passTimes_ = r_.timer_.collect();
        return false;
    }
    if (state_.perFramePending) { // the passes after the shadow maps: AO, opaque
        state_.lastStep = Refinement::Step::PerFrame;
        runPerFramePasses(false);
        r_.passTimes_ = r_.timer_.collect();
        return false;
    }
    // The per-frame work of the Pixels passes (the fog's light transmittance volumes) while
    // there is some: its next step, alone.
    bool slab = false;
    for (const pass::Pass& p : r_.passes_.passes()) {
        if (p.scope != pass::Scope::Pixels || !p.prepareStep) continue;
        gpu::TimerScope timer(r_.timer_, p.prepareName);
        if (p.receivesShadows) r_.stages_.shadows->bindForReceivers();
        if ((slab = p.prepareStep(r_.pass_))) break;
    }
    if (slab) {
        state_.lastStep = Refinement::Step::LightSlab;
        ++state_.lightSlabs;
        r_.passTimes_ = r_.timer_.collect();
        return false;
    }
    state_.lastStep = Refinement::Step::Tile;
    const glm::ivec4 tile = takeTile(state_.pending, maxTilePx);
    // The per-pixel passes over the tile and the OIT technique's margin (refineMarginPx(): what
    // its resolve reads around a pixel), so the tile comes out as in the whole frame. The fog
    // marches the texels its upsampling reads for these pixels (FogPass::march).
    const int m = r_.refineMarginPx(), width = r_.width_, height = r_.height_;
    const glm::ivec4 r(std::max(0, tile.x - m), std::max(0, tile.y - m),
                       std::min(width, tile.z + m), std::min(height, tile.w + m));
    const gpu::Texture &hdr = r_.targets_.hdr, &ldr = r_.targets_.ldr;
    // The resolve composites over hdr in the region (pass::Context::region): it starts from
    // the opaque image there every tile.
    copyRect(opaqueHdr_, hdr, r);
    r_.setRegion(r);
    r_.state_.setScissorLimit(glm::ivec4(r.x, r.y, r.z - r.x, r.w - r.y));
    r_.runPasses(pass::Scope::Pixels);
    r_.state_.setScissorLimit(std::nullopt);
    r_.state_.apply(gpu::PipelineState{}); // the scissor test off again for whoever draws next
    r_.setRegion(glm::ivec4(0, 0, width, height));
    copyRect(hdr, refinedHdr_, tile);
    copyRect(ldr, refinedLdr_, tile);
    state_.lastTile = tile;
    state_.lastRegion = r;
    ++state_.done;
    state_.pixelsDone += static_cast<long long>(tile.z - tile.x) * (tile.w - tile.y);
    r_.passTimes_ = r_.timer_.collect();
    if (!state_.pending.empty()) return false;
    // Complete: the frame targets hold the frame, as after render().
    copyRect(refinedHdr_, hdr, glm::ivec4(0, 0, width, height));
    copyRect(refinedLdr_, ldr, glm::ivec4(0, 0, width, height));
    state_.active = false;
    return true;
}

} // namespace veil::frame
