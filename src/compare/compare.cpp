#include "compare/compare.h"

#include "base/error.h"
#include "io/metrics.h"

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

} // namespace veil::compare
