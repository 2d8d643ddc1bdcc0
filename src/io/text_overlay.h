// Text burnt into images (contact sheet labels) through OpenImageIO's FreeType text renderer,
// with DejaVu Sans Mono (Debian's fonts-dejavu-core).
#pragma once

#include "base/image.h"

#include <array>
#include <string>

namespace veil::io {

// The font file used; throws veil::Error naming it when it is not installed.
std::string labelFontPath();

// Draws `text` with its top-left corner near (x, y), `sizePx` pixels high, in `color` (linear
// values written as they are), over the first three channels of `image`; throws veil::Error
// when the text cannot be rendered.
void drawText(ImageF& image, int x, int y, const std::string& text, int sizePx,
              const std::array<float, 3>& color);

} // namespace veil::io
