// Image comparison for `veil render --compare-to`, `--oit all` and the viewer's error view:
// error numbers on linear HDR radiance (io/metrics.h), a visible error image and a contact
// sheet.
#pragma once

#include "base/image.h"

#include <string>
#include <vector>

namespace veil::compare {

// Over the RGB channels of all pixels of two same-size linear images (metrics::rmse,
// metrics::psnr, metrics::peak):
//   MSE  = mean((a - b)^2),  RMSE = sqrt(MSE),
//   PSNR = 10 log10(peak^2 / MSE) dB with peak = max RGB value of the reference
// (+inf when MSE = 0; NaN when the reference is all zero and MSE > 0).
struct ImageError {
    double rmse = 0.0;
    double psnr = 0.0;
    double peak = 0.0;
};
ImageError compareLinear(const ImageF& image, const ImageF& reference);

// |image - reference| * scale per channel in linear, clamped to [0, 1], then sRGB-encoded
// (RGB, for a PNG).
constexpr float kErrorImageScale = 4.0f;
ImageF errorImage(const ImageF& image, const ImageF& reference, float scale = kErrorImageScale);

// Tiles of the same height side by side, separated by `gap` black columns; RGB.
ImageF contactSheet(const std::vector<ImageF>& tiles, int gap = 2);

// Tiles of one size in a grid, each with its lines of `labels` burnt into a black strip under
// it (DejaVu Sans Mono, io/text_overlay.h, `labelValue` on every channel), `gap` black pixels
// between cells. `columns` 0 picks the count whose sheet is nearest 16:9. RGB.
ImageF labelledContactSheet(const std::vector<ImageF>& tiles,
                            const std::vector<std::vector<std::string>>& labels, int columns = 0,
                            int gap = 4, float labelValue = 1.0f);

} // namespace veil::compare
