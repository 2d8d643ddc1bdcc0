// The viewer's screenshots (screenshot.h).
#include "viewer/screenshot.h"

#include "capture/dump.h"
#include "capture/frame_output.h"

#include "base/error.h"
#include "gpu/readback.h"
#include "io/exr_writer.h"
#include "io/image_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <vector>

namespace veil::viewer {

namespace fs = std::filesystem;

void writeShownImage(const session::ViewSession& session, const DebugView& view,
                     const std::string& path) {
    const bool exr = capture::isExrPath(path);
    if (view.active() && exr)
        io::writeExr(
            path, capture::resourceExr(view.raw(), {{"veil:resource", view.resource()},
                                                    {"veil:layer", std::to_string(view.layer())}}));
    else if (view.active())
        io::writeImage(path, view.visualized());
    else if (exr) // RGB, A, Z and the metadata
        capture::writeFrame(path, session.renderer(),
                            {session.scenePath(), session.context().renderer});
    else // the last complete frame (a refinement or a failed frame leaves it shown)
        io::writeImage(path, gpu::readTexture(session.displayTexture()));
}

std::string screenshotPair(const session::ViewSession& session, const DebugView& view,
                           const std::string& dir, int number) {
    VEIL_CHECK(fs::is_directory(dir), "screenshot folder '{}' does not exist", dir);
    const std::string stem = (fs::path(dir) / fmt::format("veil-{:04d}", number)).string();
    writeShownImage(session, view, stem + ".png");
    writeShownImage(session, view, stem + ".exr");
    return stem + ".png";
}

void writeWindowImage(const std::string& path, int width, int height) {
    ImageF img(width, height, 4);
    std::vector<float> rows(img.pixels.size());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, rows.data());
    const std::size_t row = std::size_t(width) * 4;
    for (int y = 0; y < height; ++y) // GL's rows start at the bottom
        std::copy_n(rows.begin() + (height - 1 - y) * row, row, img.pixels.begin() + y * row);
    for (std::size_t i = 3; i < img.pixels.size(); i += 4)
        img.pixels[i] = 1.0f;
    io::writeImage(path, img);
}

} // namespace veil::viewer
