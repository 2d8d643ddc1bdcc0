#include "viewer/debug_view.h"

#include "viewer/session/view_session.h"

#include "base/error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace veil::viewer {

std::vector<DebugViewEntry> debugViewEntries(const frame::Renderer& renderer) {
    std::vector<DebugViewEntry> out;
    for (const std::string& name : renderer.passes().resources()) {
        DebugViewEntry e;
        e.resource = name;
        const gpu::Texture* t = renderer.resourceTexture(name);
        if (!t || !*t) {
            e.reason = name.rfind("oit.", 0) == 0
                           ? "the storage of the OIT technique '" + renderer.oitName() +
                                 "' as a whole (no frame texture; its targets are listed as oit." +
                                 renderer.oitName() + ".*)"
                           : "no texture behind this resource";
            if (name.rfind("oit.", 0) == 0)
                e.bytes = std::size_t(renderer.width()) * renderer.height() *
                          renderer.technique().bytesPerPixel();
        } else {
            e.reason = capture::whyNotReadable(*t);
            e.layers = capture::resourceLayers(*t);
            e.format = capture::formatName(t->format());
            e.bytes = std::size_t(t->width()) * t->height() * e.layers *
                      capture::bytesPerTexel(t->format());
        }
        out.push_back(std::move(e));
    }
    return out;
}

void DebugView::select(std::string resource, int layer) {
    resource_ = std::move(resource);
    layer_ = std::max(0, layer);
}

bool isCountResource(const std::string& resource) {
    const std::string suffix = ".fragments_per_pixel";
    return resource.size() > suffix.size() &&
           resource.compare(resource.size() - suffix.size(), suffix.size(), suffix) == 0;
}

glm::vec3 heatRamp(float t) {
    static const glm::vec3 stops[] = {{0.0f, 0.0f, 0.0f}, {0.1f, 0.1f, 0.8f},  {0.8f, 0.1f, 0.7f},
                                      {1.0f, 0.5f, 0.0f}, {1.0f, 0.95f, 0.1f}, {1.0f, 1.0f, 1.0f}};
    const float x = std::clamp(t, 0.0f, 1.0f) * 5.0f;
    const int i = std::min(4, static_cast<int>(x));
    return glm::mix(stops[i], stops[i + 1], x - static_cast<float>(i));
}

void DebugView::update(const session::ViewSession& session) {
    if (!active()) return;
    heat_ = false;
    if (errorView()) {
        if (!error_) error_ = std::make_unique<ReferenceErrorView>();
        raw_ = error_->update(session);
        layer_ = 0;
    } else {
        const gpu::Texture* t = session.renderer().resourceTexture(resource_);
        VEIL_CHECK(t && *t, "debug view '{}': the frame has no texture for it", resource_);
        layer_ = std::min(layer_, capture::resourceLayers(*t) - 1);
        raw_ = capture::readResourceImage(*t, layer_);
        heat_ = isCountResource(resource_) && raw_.channels.size() == 1;
    }
    visualize();
}

void DebugView::visualize() {
    const std::size_t texels = std::size_t(raw_.width) * raw_.height;
    const int c = static_cast<int>(raw_.channels.size());
    // The finite range of the shown channels (RGB of colour; depth without the cleared 1).
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (std::size_t i = 0; i < texels; ++i)
        for (int k = 0; k < std::min(c, 3); ++k) {
            const float v = raw_.pixels[i * c + k];
            if (!std::isfinite(v) || (raw_.depth && v >= 1.0f)) continue;
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    if (!(lo <= hi)) lo = 0.0f, hi = 1.0f;
    if (c >= 3 || heat_) lo = std::min(lo, 0.0f); // colours, errors and counts from zero
    if (hi - lo < 1e-30f) {                       // a constant: shown against [0, max(1, value)]
        lo = std::min(lo, 0.0f);
        hi = std::max(hi, 1.0f);
    }
    lo_ = lo;
    hi_ = hi;
    rgba_.assign(texels * 4, 1.0f);
    for (std::size_t i = 0; i < texels; ++i) {
        if (heat_) {
            const float v = raw_.pixels[i];
            const glm::vec3 h =
                std::isfinite(v) ? heatRamp((v - lo) / (hi - lo)) : glm::vec3(1, 0, 0);
            rgba_[i * 4 + 0] = h.r;
            rgba_[i * 4 + 1] = h.g;
            rgba_[i * 4 + 2] = h.b;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const float v = raw_.pixels[i * c + (c == 1 ? 0 : k)];
            rgba_[i * 4 + k] = std::isfinite(v) ? std::clamp((v - lo) / (hi - lo), 0.0f, 1.0f)
                                                : (k == 0 ? 1.0f : 0.0f); // NaN/inf in red
        }
    }
    if (!texture_ || texture_.width() != raw_.width || texture_.height() != raw_.height) {
        texture_ = gpu::Texture(GL_TEXTURE_2D);
        texture_.storage2D(1, GL_RGBA8, raw_.width, raw_.height)
            .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    // Row 0 of the upload is GL's bottom row.
    std::vector<float> flipped(rgba_.size());
    const std::size_t row = std::size_t(raw_.width) * 4;
    for (int y = 0; y < raw_.height; ++y)
        std::copy_n(rgba_.begin() + (raw_.height - 1 - y) * row, row, flipped.begin() + y * row);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(texture_.id(), 0, 0, 0, raw_.width, raw_.height, GL_RGBA, GL_FLOAT,
                        flipped.data());
}

ImageF DebugView::visualized() const {
    ImageF img(raw_.width, raw_.height, 4);
    img.pixels = rgba_;
    return img;
}

} // namespace veil::viewer
