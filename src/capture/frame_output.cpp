// Frames into image files (frame_output.h).
#include "capture/frame_output.h"

#include "io/exr_writer.h"
#include "io/image_io.h"

#include <algorithm>
#include <cctype>

namespace veil::capture {

bool isExrPath(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".exr";
}

void writeFrame(const std::filesystem::path& path, const RenderedFrame& frame,
                const RenderMetadata& metadata, bool half) {
    if (isExrPath(path))
        io::writeExr(path, makeExr(frame.hdr, frame.extras, metadata, half));
    else
        io::writeImage(path, frame.ldr);
}

void writeFrame(const std::filesystem::path& path, const frame::Renderer& renderer,
                const FrameOutput& output) {
    if (!isExrPath(path)) {
        io::writeImage(path, renderer.readLdr());
        return;
    }
    const FrameExtras extras = captureExtras(renderer, false);
    RenderMetadata metadata = describeRender(
        output.scene, renderer.oitName(), renderer.technique().properties().values(),
        renderer.camera().name, extras, renderer.width(), renderer.height(), output.glRenderer);
    for (const auto& [key, value] : output.strings.items())
        metadata.strings[key] = value;
    io::writeExr(path, makeExr(renderer.readHdr(), extras, metadata, output.half));
}

} // namespace veil::capture
