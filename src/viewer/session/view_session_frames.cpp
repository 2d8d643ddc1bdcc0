// The session's frames (view_session.h): in one piece, or refined in tiles with the budget's
// tile sizes, and what the refinements did per UI frame.
#include "viewer/session/view_session.h"

#include "fog/scattered_light_cache.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace veil::session {

void ViewSession::copyToDisplay() {
    const gpu::Texture& ldr = renderer_->ldrTexture();
    if (!display_ || display_.width() != ldr.width() || display_.height() != ldr.height()) {
        display_ = gpu::Texture(GL_TEXTURE_2D);
        display_.storage2D(1, GL_RGBA8, ldr.width(), ldr.height())
            .parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    }
    glCopyImageSubData(ldr.id(), GL_TEXTURE_2D, 0, 0, 0, 0, display_.id(), GL_TEXTURE_2D, 0, 0, 0,
                       0, ldr.width(), ldr.height(), 1);
}

namespace {
double passMs(const frame::Renderer& r) {
    double ms = 0.0;
    for (const auto& p : r.passTimes())
        ms += p.milliseconds;
    return ms;
}
} // namespace

bool ViewSession::frameFailed(const Error& e) {
    frameFailed_ = true;
    renderer_->cancelRefinement();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    record(fmt::format("frame failed (the last good frame stays): {}", e.what()));
    return false;
}

bool ViewSession::scatteredLightConverging() const {
    const volume::FogPass* fog = renderer_->fog();
    const volume::ScatteredLightCache* cache = fog ? fog->scatteredLightCache() : nullptr;
    return cache && cache->converging();
}

bool ViewSession::renderFrame(bool refine) {
    if (frameFailed_) return false; // until the next change: the error would only repeat
    try {
        // The progressive bake (setProgressiveBake): every frame runs the cache's bake for the
        // budget; while it converges frames come in one piece, and the version moves on after
        // each so that the window draws the next (nothing else would ask for it).
        // It also fills what the last frame's passes left of render.fog_scattered_light_frame_ms.
        const scene::RenderSettings& rs = scene_->render;
        renderer_->setScatteredLightBudgetMs(
            progressiveBake_
                ? volume::progressiveBakeMs(rs.fogScatteredLightBudgetMs,
                                            rs.fogScatteredLightFrameMs, passMs(*renderer_))
                : 0.0);
        const bool converging = scatteredLightConverging();
        const int t = refineTilePx_;
        if (refine && !converging && t > 0 && (width_ > t || height_ > t)) {
            renderer_->beginRefinement(t);
            refineLog_.tilePx = t;
            refineLog_.tiles = renderer_->refinement().tiles;
            refineLog_.steps = 0;
            refineLog_.minTilePx = 0;
            if (refineKey() != refineEstimateKey_) refineMsPerPixel_ = -1.0;
            refineLog_.uiFrames = 0;
            refineLog_.maxTilesPerUiFrame = 0;
            refineLog_.maxPixelsPerUiFrame = 0;
            refineLog_.lightSlabs = 0;
            refineLog_.shadowSteps = 0;
            refineLog_.maxPerFrameStepsPerUiFrame = 0;
            refineLog_.maxLightSlabsPerUiFrame = 0;
            refineLog_.maxUiFrameMs = passMs(*renderer_);
            refineLog_.complete = false;
            refineLog_.firstUiFrameMs = passMs(*renderer_);
            refineLog_.maxTileUiFrameMs = 0.0;
            refineLog_.totalMs = refineLog_.firstUiFrameMs;
            uiFrameRefines_ = true;
            return false;
        }
        renderer_->cancelRefinement();
        renderer_->render();
        uiFramePixels_ += static_cast<long long>(width_) * height_;
        copyToDisplay();
        if (scatteredLightConverging()) ++version_;
        return true;
    } catch (const Error& e) {
        return frameFailed(e);
    }
}

bool ViewSession::refineStep() {
    if (!renderer_->refining()) return false;
    try {
        const int tilePx = nextRefineTilePx();
        const bool done = renderer_->refineStep(tilePx == refineTilePx_ ? 0 : tilePx);
        const frame::Renderer::Refinement& f = renderer_->refinement();
        const double ms = passMs(*renderer_);
        using Step = frame::Renderer::Refinement::Step;
        if (f.lastStep == Step::LightSlab) {
            ++uiFrameLightSlabs_;
            ++refineLog_.lightSlabs;
        } else if (f.lastStep == Step::ShadowBand || f.lastStep == Step::PerFrame) {
            ++uiFramePerFrameSteps_;
            refineLog_.shadowSteps += f.lastStep == Step::ShadowBand;
        } else if (f.lastStep == Step::Tile) {
            const glm::ivec4 r = f.lastRegion, t = f.lastTile;
            const long long pixels = static_cast<long long>(r.z - r.x) * (r.w - r.y);
            ++uiFrameTiles_;
            uiFramePixels_ += pixels;
            ++refineLog_.steps;
            const int side = std::max(t.z - t.x, t.w - t.y);
            refineLog_.minTilePx =
                refineLog_.minTilePx > 0 ? std::min(refineLog_.minTilePx, side) : side;
            if (pixels > 0) {
                refineMsPerPixel_ = ms / static_cast<double>(pixels);
                refineEstimateKey_ = refineKey();
            }
        }
        uiFrameMs_ += ms;
        uiFrameRefines_ = true;
        if (!done) return false;
        copyToDisplay();
        refineLog_.complete = true;
        ++refineLog_.completed;
        if (scatteredLightConverging()) ++version_; // the next frame goes on with the bake
        return true;
    } catch (const Error& e) {
        return frameFailed(e);
    }
}

void ViewSession::setRefineTilePx(int px) {
    if (px < 0) {
        record(fmt::format("refine tile size {} is negative (0 = off)", px));
        return;
    }
    if (px == refineTilePx_) return;
    refineTilePx_ = px;
    status_ = px > 0 ? fmt::format("refining in {} px tiles", px) : "refinement off";
    ++version_;
}

void ViewSession::setRefineBudgetMs(double ms) {
    if (!(ms >= 0.0) || !std::isfinite(ms)) {
        record(fmt::format("refine budget {} ms is not a finite number >= 0 (0 = off)", ms));
        return;
    }
    refineBudgetMs_ = ms;
}

std::string ViewSession::refineKey() const {
    return fmt::format("{}|{}|{}|{}x{}", rebuilds_, renderer_->oitName(),
                       renderer_->shadowTechnique().name(), width_, height_);
}

int ViewSession::nextRefineTilePx() const {
    const int t = refineTilePx_;
    if (refineBudgetMs_ <= 0.0 || t <= kMinRefineTilePx) return t;
    if (refineMsPerPixel_ < 0.0 || refineKey() != refineEstimateKey_)
        return kMinRefineTilePx; // nothing measured for this frame yet: the smallest tile first
    // The margin around the tile runs the per-pixel passes too (frame::Renderer::refineStep).
    const int m = renderer_->refineMarginPx();
    auto cost = [&](int s) { return refineMsPerPixel_ * double(s + 2 * m) * double(s + 2 * m); };
    int s = t;
    while (s > kMinRefineTilePx && cost(s) > refineBudgetMs_)
        s = std::max(kMinRefineTilePx, (s + 1) / 2);
    return s;
}

void ViewSession::endUiFrame() {
    if (uiFrameRefines_) {
        ++refineLog_.uiFrames;
        refineLog_.maxTilesPerUiFrame = std::max(refineLog_.maxTilesPerUiFrame, uiFrameTiles_);
        refineLog_.maxPixelsPerUiFrame = std::max(refineLog_.maxPixelsPerUiFrame, uiFramePixels_);
        refineLog_.maxLightSlabsPerUiFrame =
            std::max(refineLog_.maxLightSlabsPerUiFrame, uiFrameLightSlabs_);
        refineLog_.maxPerFrameStepsPerUiFrame =
            std::max(refineLog_.maxPerFrameStepsPerUiFrame, uiFramePerFrameSteps_);
        if (uiFrameTiles_ > 0)
            refineLog_.maxTileUiFrameMs = std::max(refineLog_.maxTileUiFrameMs, uiFrameMs_);
        refineLog_.maxUiFrameMs = std::max(refineLog_.maxUiFrameMs, uiFrameMs_);
        refineLog_.totalMs += uiFrameMs_;
    }
    uiFrameMs_ = 0.0;
    uiFrameTiles_ = 0;
    uiFrameLightSlabs_ = 0;
    uiFramePerFrameSteps_ = 0;
    uiFramePixels_ = 0;
    uiFrameRefines_ = false;
}

} // namespace veil::session
