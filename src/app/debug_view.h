// The viewer's debug views: any frame resource (Renderer::passes().resources(), so a new
// technique's buffers appear without viewer code) shown in place of the frame. A view reads
// the resource's texture back (app/resource_image.h: the same values `veil render --dump`
// writes), maps its finite range to [0, 1] (depth: the drawn range, without the cleared 1) and
// uploads that as an RGBA8 image; `raw()` keeps the values for the EXR screenshot.
#pragma once

#include "app/resource_image.h"
#include "frame/renderer.h"

#include <string>
#include <vector>

namespace veil::app {

struct DebugViewEntry {
    std::string resource;
    int layers = 1;     // light views (arrays) or slices (3D)
    std::string reason; // why it cannot be shown ("" = it can)
    std::size_t bytes = 0;
    std::string format;
};

// Every resource of the frame, in the order the passes declare them.
std::vector<DebugViewEntry> debugViewEntries(const frame::Renderer& renderer);

class DebugView {
public:
    // "" = the frame itself (no debug view).
    void select(std::string resource, int layer = 0);
    const std::string& resource() const { return resource_; }
    int layer() const { return layer_; }
    bool active() const { return !resource_.empty(); }
    // Reads the selected resource of the last frame; throws veil::Error when it has no
    // readable texture.
    void update(const frame::Renderer& renderer);
    const gpu::Texture& texture() const { return texture_; }
    const ResourceImage& raw() const { return raw_; }
    float lo() const { return lo_; }
    float hi() const { return hi_; }
    // The visualized image (RGBA, [0, 1], row 0 = top) as uploaded.
    ImageF visualized() const;

private:
    std::string resource_;
    int layer_ = 0;
    ResourceImage raw_;
    std::vector<float> rgba_;
    float lo_ = 0.0f, hi_ = 1.0f;
    gpu::Texture texture_{gpu::NoCreate};
};

} // namespace veil::app
