#include "io/text_overlay.h"

#include "base/error.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <filesystem>

namespace veil::io {

std::string labelFontPath() {
    const char* path = "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf";
    VEIL_CHECK(std::filesystem::is_regular_file(path),
               "label font '{}' is missing (Debian package fonts-dejavu-core; "
               "scripts/install-deps.sh installs it)",
               path);
    return path;
}

void drawText(ImageF& image, int x, int y, const std::string& text, int sizePx,
              const std::array<float, 3>& color) {
    VEIL_CHECK(image.channels >= 3, "text needs an RGB image");
    // An RGB view of the image, drawn into, copied back.
    OIIO::ImageBuf buf(OIIO::ImageSpec(image.width, image.height, 3, OIIO::TypeDesc::FLOAT));
    for (int py = 0; py < image.height; ++py)
        for (int px = 0; px < image.width; ++px) {
            const float rgb[3] = {image.at(px, py, 0), image.at(px, py, 1), image.at(px, py, 2)};
            buf.setpixel(px, py, rgb, 3);
        }
    // OIIO places the text's baseline at y: move it down by the ascent (about 0.8 em).
    const float c[3] = {color[0], color[1], color[2]};
    const bool ok = OIIO::ImageBufAlgo::render_text(buf, x, y + (sizePx * 4) / 5, text, sizePx,
                                                    labelFontPath(), OIIO::cspan<float>(c, 3));
    VEIL_CHECK(ok, "cannot draw the label '{}': {}", text, buf.geterror());
    for (int py = 0; py < image.height; ++py)
        for (int px = 0; px < image.width; ++px) {
            float rgb[3];
            buf.getpixel(px, py, rgb, 3);
            for (int ch = 0; ch < 3; ++ch)
                image.at(px, py, ch) = rgb[ch];
        }
}

} // namespace veil::io
