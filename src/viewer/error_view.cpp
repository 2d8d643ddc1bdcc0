#include "viewer/error_view.h"

#include "viewer/session/view_session.h"

#include <algorithm>
#include <cmath>

namespace veil::viewer {

nlohmann::json ReferenceErrorView::referenceProperties(const frame::Renderer& renderer) {
    if (renderer.oitName() == "reference") return renderer.technique().properties().values();
    return {{"pool_overflow", "drop"}};
}

const capture::ResourceImage& ReferenceErrorView::update(const session::ViewSession& session) {
    const frame::Renderer& shown = session.renderer();
    const nlohmann::json properties = referenceProperties(shown);
    if (!reference_ || builtFor_ != session.rebuilds()) {
        reference_.reset(); // before the new one: one reference's targets at a time
        reference_ = std::make_unique<frame::Renderer>(
            session.scene(), session.context(),
            frame::RendererOptions{shown.width(), shown.height(), shown.camera().name, "reference",
                                   properties});
        builtFor_ = session.rebuilds();
        valuesSeen_ = session.valueChanges();
        properties_ = properties;
    }
    if (properties_ != properties) {
        reference_->setOitTechnique("reference", properties, "the error view's reference");
        properties_ = properties;
    }
    if (valuesSeen_ != session.valueChanges()) {
        reference_->sceneValuesChanged(); // a light or volume edited in place
        valuesSeen_ = session.valueChanges();
    }
    reference_->resize(shown.width(), shown.height());
    reference_->setCamera(shown.camera());
    reference_->render();
    const ImageF a = shown.readHdr(), b = reference_->readHdr();
    error_ = compare::compareLinear(a, b);
    image_ = {};
    image_.width = a.width;
    image_.height = a.height;
    image_.channels = {"R", "G", "B"};
    const std::size_t texels = std::size_t(a.width) * a.height;
    image_.pixels.resize(texels * 3);
    maxAbs_ = 0.0;
    for (std::size_t i = 0; i < texels; ++i)
        for (int k = 0; k < 3; ++k) {
            const float d = std::fabs(a.pixels[i * a.channels + k] - b.pixels[i * b.channels + k]);
            image_.pixels[i * 3 + k] = d;
            maxAbs_ = std::max(maxAbs_, double(d));
        }
    return image_;
}

} // namespace veil::viewer
