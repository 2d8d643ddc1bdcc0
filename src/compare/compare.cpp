#include "compare/compare.h"

#include "base/error.h"
#include "io/metrics.h"
#include "io/text_overlay.h"

#include <algorithm>
#include <cmath>

namespace veil::compare {

ImageError compareLinear(const ImageF& image, const ImageF& reference) {
    return {metrics::rmse(image, reference), metrics::psnr(image, reference),
            metrics::peak(reference)};
}

ImageF errorImage(const ImageF& image, const ImageF& reference, float scale) {
    VEIL_CHECK(image.width == reference.width && image.height == reference.height &&
                   image.channels >= 3 && reference.channels >= 3,
               "cannot compare a {}x{}x{} image with a {}x{}x{} one", image.width, image.height,
               image.channels, reference.width, reference.height, reference.channels);
    ImageF out(image.width, image.height, 3);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c)
                out.at(x, y, c) = metrics::srgbEncode(
                    std::abs(image.at(x, y, c) - reference.at(x, y, c)) * scale);
    return out;
}

ImageF contactSheet(const std::vector<ImageF>& tiles, int gap) {
    VEIL_CHECK(!tiles.empty(), "contact sheet needs at least one image");
    int width = 0;
    for (const ImageF& t : tiles) {
        VEIL_CHECK(t.height == tiles[0].height && t.channels >= 3,
                   "contact sheet tiles must share their height");
        width += t.width;
    }
    width += gap * static_cast<int>(tiles.size() - 1);
    ImageF sheet(width, tiles[0].height, 3);
    int x0 = 0;
    for (const ImageF& t : tiles) {
        for (int y = 0; y < t.height; ++y)
            for (int x = 0; x < t.width; ++x)
                for (int c = 0; c < 3; ++c)
                    sheet.at(x0 + x, y, c) = t.at(x, y, c);
        x0 += t.width + gap;
    }
    return sheet;
}

ImageF labelledContactSheet(const std::vector<ImageF>& tiles,
                            const std::vector<std::vector<std::string>>& labels, int columns,
                            int gap, float labelValue) {
    VEIL_CHECK(!tiles.empty(), "contact sheet needs at least one image");
    VEIL_CHECK(labels.size() == tiles.size(), "contact sheet: {} labels for {} tiles",
               labels.size(), tiles.size());
    const int w = tiles[0].width, h = tiles[0].height;
    for (const ImageF& t : tiles)
        VEIL_CHECK(t.width == w && t.height == h && t.channels >= 3,
                   "contact sheet tiles must share their size");
    std::size_t lines = 1, longest = 1;
    for (const auto& l : labels) {
        lines = std::max(lines, l.size());
        for (const std::string& text : l)
            longest = std::max(longest, text.size());
    }
    // A sixteenth of the tile's width, smaller when the longest label would not fit (a
    // DejaVu Sans Mono character is 0.6 em wide), at least 8 px.
    const int fit = static_cast<int>(0.9 * w / (0.6 * double(longest)));
    const int px = std::clamp(std::min(w / 16, fit), 8, 18), lineHeight = px + px / 4;
    const int strip = static_cast<int>(lines) * lineHeight + px / 2;
    const int cellW = w + gap, cellH = h + strip + gap;
    const int n = static_cast<int>(tiles.size());
    if (columns <= 0) {
        double best = 1e300;
        for (int c = 1; c <= n; ++c) {
            const int rows = (n + c - 1) / c;
            const double off =
                std::abs(std::log(double(c * cellW) / (rows * cellH) / (16.0 / 9.0)));
            if (off < best) best = off, columns = c;
        }
    }
    const int rows = (n + columns - 1) / columns;
    ImageF sheet(columns * cellW - gap, rows * cellH - gap, 3);
    for (int i = 0; i < n; ++i) {
        const int x0 = (i % columns) * cellW, y0 = (i / columns) * cellH;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c)
                    sheet.at(x0 + x, y0 + y, c) = tiles[i].at(x, y, c);
        ImageF caption(w, strip, 3); // drawn apart: text rendering copies its image
        for (std::size_t l = 0; l < labels[i].size(); ++l)
            io::drawText(caption, px / 4, px / 4 + static_cast<int>(l) * lineHeight, labels[i][l],
                         px, {labelValue, labelValue, labelValue});
        for (int y = 0; y < strip; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c)
                    sheet.at(x0 + x, y0 + h + y, c) = caption.at(x, y, c);
    }
    return sheet;
}

} // namespace veil::compare
