// The viewer's screenshots: what it shows written to image files, for the panel's Screenshot
// button, a script's screenshot actions and `veil view --frames N --screenshot`.
#pragma once

#include "viewer/debug_view.h"
#include "viewer/session/view_session.h"

#include <string>

namespace veil::viewer {

// One file: .png = the shown image (the last complete frame, or the debug view), .exr = the
// frame's linear HDR as `veil render -o out.exr` writes it (capture::writeFrame), or the debug
// view's raw resource values.
void writeShownImage(const session::ViewSession& session, const DebugView& view,
                     const std::string& path);

// Writes `dir`/veil-NNNN.png (the shown image) and .exr beside it (writeShownImage); returns
// the PNG path.
std::string screenshotPair(const session::ViewSession& session, const DebugView& view,
                           const std::string& dir, int number);

// The whole window (the default framebuffer's back buffer, `width` x `height`, panel
// included) as an opaque image file.
void writeWindowImage(const std::string& path, int width, int height);

} // namespace veil::viewer
