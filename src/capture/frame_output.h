// One rendered frame into an image file, the one place that turns a frame into what
// `veil render -o`, `veil render --frames`, the viewer's screenshots and the Python module
// write: .png gets the tone-mapped sRGB image, .exr the linear HDR radiance with A, Z (and
// AOVs) and the metadata naming what was rendered (capture/exr_output.h).
#pragma once

#include "capture/exr_output.h"
#include "capture/frame_capture.h"
#include "frame/renderer.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace veil::capture {

// Whether `path` ends in .exr (any case): an EXR frame, else an 8-bit image.
bool isExrPath(const std::filesystem::path& path);

// A read-back frame (capture/frame_capture.h): .exr gets makeExr(frame.hdr, frame.extras,
// metadata, half), anything else frame.ldr.
void writeFrame(const std::filesystem::path& path, const RenderedFrame& frame,
                const RenderMetadata& metadata, bool half = false);

// What to put into an EXR of a live renderer's frame beyond its pixels.
struct FrameOutput {
    std::filesystem::path scene;                       // veil:scene, veil:scene_sha256
    std::string glRenderer;                            // veil:gl_renderer
    bool half = false;                                 // half-float channels
    nlohmann::json strings = nlohmann::json::object(); // more header strings (veil:frame)
};

// What the last render() of `renderer` left: .exr gets the linear HDR radiance, A, Z and
// describeRender's metadata (plus `output.strings`), anything else the tone-mapped image.
void writeFrame(const std::filesystem::path& path, const frame::Renderer& renderer,
                const FrameOutput& output);

} // namespace veil::capture
