// What `veil render -o out.exr` writes beyond the radiance: the opaque surface's view depth
// (Z), optional arbitrary output variables (AOVs) and metadata naming what was rendered.
//
// Channels (float32 unless --half):
//   R, G, B  linear HDR radiance of the frame (what the PNG tone-maps)
//   A        1 everywhere: the background colour is part of R, G, B, so the image is opaque;
//            there is nothing behind it to composite over
//   Z        view depth of the nearest opaque surface in scene units (distance along the
//            camera's forward axis, not along the ray); where the ray hits no opaque surface,
//            the far plane's depth (min(far, 65504) in half files), recorded in the header as
//            veil:background_depth, so Z is finite and tools that compare every channel
//            (idiff) see equal renders as equal. Transparent surfaces and fog write no depth.
//            (FrameExtras::viewDepth keeps +inf there.)
//   --aov fog: fog.R, fog.G, fog.B (radiance the fog scatters toward the camera in front of
//            the opaque surface) and fog.transmittance (of the fog alone, along the same
//            segment), as the fog pass computed them (upsampled to full size by nearest
//            neighbour when render.fog_resolution > 1).
#pragma once

#include "base/image.h"
#include "frame/renderer.h"
#include "io/exr_writer.h"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace veil::capture {

struct FrameExtras {
    ImageF viewDepth;        // 1 channel, Z as above
    ImageF fogRadiance;      // RGB; empty unless asked for
    ImageF fogTransmittance; // 1 channel; empty unless asked for
    glm::mat4 view{1.0f}, projection{1.0f};
};

// Reads what the last render() of `renderer` left in its targets. `fogAov` asks for the fog
// AOVs (throws veil::Error when the scene has no fog).
FrameExtras captureExtras(const frame::Renderer& renderer, bool fogAov);

// Depth-buffer values (window depth in [0, 1], glDepthRange 0..1) to view depth through the
// inverse of `projection`; 1.0 (the clear value) becomes +inf.
ImageF linearViewDepth(const ImageF& windowDepth, const glm::mat4& projection);

// Header metadata of an output: string attributes as JSON (also put into the --report).
struct RenderMetadata {
    nlohmann::json strings = nlohmann::json::object(); // attribute name -> string value
    glm::mat4 view{1.0f}, projection{1.0f};
};

// The EXR for a frame: channels as above, `metadata` as header attributes (strings, plus the
// matrices as worldtocamera / worldtoscreen (OpenEXR worldToCamera / worldToNDC) and
// veil:projection), and veil:background_depth (backgroundDepth).
// Z of pixels without an opaque surface: the far plane's view depth of `projection` (65504,
// the largest half, when the far plane is at infinity or, for `half`, beyond it).
float backgroundDepth(const glm::mat4& projection, bool half);

io::ExrImage makeExr(const ImageF& hdr, const FrameExtras& extras, const RenderMetadata& metadata,
                     bool half);

// Adds a layer of an image's RGB as `<layer>.R`, `<layer>.G`, `<layer>.B` (OpenEXR's layer
// naming), e.g. one per technique of `veil render --oit all -o all.exr`.
void addRgbLayer(io::ExrImage& exr, const std::string& layer, const ImageF& rgb);

} // namespace veil::capture

namespace veil::capture {

// The metadata of one rendered frame: Software, veil:version, veil:commit, veil:scene (absolute
// path), veil:scene_sha256, veil:oit, veil:oit_properties (the effective values as JSON text),
// veil:camera, veil:size ("WxH"), veil:gl_renderer, veil:channels (what A and Z mean), and the
// camera's view and projection matrices.
RenderMetadata describeRender(const std::filesystem::path& scene, const std::string& oit,
                              const nlohmann::json& oitProperties, const std::string& camera,
                              const FrameExtras& extras, int width, int height,
                              const std::string& glRenderer);

// The metadata as JSON for --report: the strings, and the matrices as 16 numbers each
// (column-major, as GLM and OpenEXR's row-vector m44f store them).
nlohmann::json metadataJson(const RenderMetadata& metadata);

} // namespace veil::capture
