// The viewer's debug views: any frame resource (Renderer::passes().resources(), so a new
// technique's buffers appear without viewer code) shown in place of the frame. A view reads
// the resource's texture back (capture/resource_image.h: the same values `veil render --dump`
// writes), maps its finite range to [0, 1] (depth: the drawn range, without the cleared 1) and
// uploads that as an RGBA8 image; `raw()` keeps the values for the EXR screenshot.
// Counts (a resource named *.fragments_per_pixel: `reference`'s per-pixel list lengths) are
// shown as a heat map of [0, max] (heatRamp(), the panel draws its legend). One view is the
// viewer's own, not a frame resource: kReferenceErrorView, |frame - reference| of the linear
// radiance (viewer/error_view.h), rendered only while it is shown.
#pragma once

#include "capture/resource_image.h"
#include "frame/renderer.h"
#include "viewer/error_view.h"

#include <glm/glm.hpp>

#include <memory>
#include <string>
#include <vector>

namespace veil::viewer {

struct DebugViewEntry {
    std::string resource;
    int layers = 1;     // light views (arrays) or slices (3D)
    std::string reason; // why it cannot be shown ("" = it can)
    std::size_t bytes = 0;
    std::string format;
};

// Every resource of the frame, in the order the passes declare them.
std::vector<DebugViewEntry> debugViewEntries(const frame::Renderer& renderer);

// Whether a resource holds counts, shown as a heat map from 0 to its maximum.
bool isCountResource(const std::string& resource);
// The heat map's colour of t in [0, 1]: black, blue, magenta, orange, yellow, white.
glm::vec3 heatRamp(float t);

class DebugView {
public:
    // "" = the frame itself (no debug view).
    void select(std::string resource, int layer = 0);
    const std::string& resource() const { return resource_; }
    int layer() const { return layer_; }
    bool active() const { return !resource_.empty(); }
    // Reads the selected resource of the session's last frame (or renders the error view);
    // throws veil::Error when it has no readable texture.
    void update(const session::ViewSession& session);
    bool heatMap() const { return heat_; }
    bool errorView() const { return resource_ == kReferenceErrorView; }
    // The error view's RMSE and largest difference (valid after update() of it).
    const ReferenceErrorView* error() const { return error_.get(); }
    const gpu::Texture& texture() const { return texture_; }
    const capture::ResourceImage& raw() const { return raw_; }
    float lo() const { return lo_; }
    float hi() const { return hi_; }
    // The visualized image (RGBA, [0, 1], row 0 = top) as uploaded.
    ImageF visualized() const;

private:
    void visualize();

    std::string resource_;
    bool heat_ = false;
    std::unique_ptr<ReferenceErrorView> error_;
    int layer_ = 0;
    capture::ResourceImage raw_;
    std::vector<float> rgba_;
    float lo_ = 0.0f, hi_ = 1.0f;
    gpu::Texture texture_{gpu::NoCreate};
};

} // namespace veil::viewer
