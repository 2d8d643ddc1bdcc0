#include "app/compare.h"

#include "base/error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace veil::app {

namespace {
float srgbEncode(float c) { // IEC 61966-2-1
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

void checkSameSize(const ImageF& a, const ImageF& b) {
    VEIL_CHECK(a.width == b.width && a.height == b.height && a.channels >= 3 && b.channels >= 3,
               "cannot compare a {}x{}x{} image with a {}x{}x{} one", a.width, a.height, a.channels,
               b.width, b.height, b.channels);
}
} // namespace

ImageError compareLinear(const ImageF& image, const ImageF& reference) {
    checkSameSize(image, reference);
    double sum = 0.0, peak = 0.0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c) {
                const double d = double(image.at(x, y, c)) - double(reference.at(x, y, c));
                sum += d * d;
                peak = std::max(peak, double(reference.at(x, y, c)));
            }
    const double mse = sum / (3.0 * image.width * image.height);
    ImageError e;
    e.rmse = std::sqrt(mse);
    e.peak = peak;
    e.psnr = mse == 0.0   ? std::numeric_limits<double>::infinity()
             : peak > 0.0 ? 10.0 * std::log10(peak * peak / mse)
                          : std::numeric_limits<double>::quiet_NaN();
    return e;
}

ImageF errorImage(const ImageF& image, const ImageF& reference, float scale) {
    checkSameSize(image, reference);
    ImageF out(image.width, image.height, 3);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c)
                out.at(x, y, c) =
                    srgbEncode(std::abs(image.at(x, y, c) - reference.at(x, y, c)) * scale);
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

} // namespace veil::app
