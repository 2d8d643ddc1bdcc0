// The viewer's live error against `reference`: the same frame (scene, camera, size, the
// session's live values) rendered by a second renderer with the exact sorted composite, and
// |frame - reference| per RGB channel of the linear HDR radiance, with its RMSE
// (compare/compare.h). It lives in the viewer, not in the frame: nothing of it runs unless the
// view is shown, and the reference renderer is kept (rebuilt only when the session builds a
// new scene) so a camera move costs one reference frame.
#pragma once

#include "capture/resource_image.h"
#include "compare/compare.h"
#include "frame/renderer.h"

#include <memory>

namespace veil::session {
class ViewSession;
}

namespace veil::viewer {

// The debug view name of the error image (not a frame resource).
inline constexpr const char* kReferenceErrorView = "error vs reference";

class ReferenceErrorView {
public:
    // Renders the session's last frame with `reference` and returns |hdr - reference hdr|
    // (channels R, G, B; row 0 = top). Throws veil::Error when the reference cannot render.
    const capture::ResourceImage& update(const session::ViewSession& session);
    // Over all pixels and RGB channels of the last update (compare::compareLinear).
    const compare::ImageError& error() const { return error_; }
    double maxAbs() const { return maxAbs_; }
    // The reference renderer's OIT properties: the session's when it renders with
    // `reference` (so the error is exactly zero there), else the defaults with
    // pool_overflow = drop (the viewer's default).
    static nlohmann::json referenceProperties(const frame::Renderer& renderer);

private:
    std::unique_ptr<frame::Renderer> reference_;
    std::uint64_t builtFor_ =
        ~std::uint64_t(0);         // session::ViewSession::rebuilds() it was built for
    std::uint64_t valuesSeen_ = 0; // session::ViewSession::valueChanges() applied
    nlohmann::json properties_;
    capture::ResourceImage image_;
    compare::ImageError error_;
    double maxAbs_ = 0.0;
};

} // namespace veil::viewer
