#include "io/image_io.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/half.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdint>

namespace veil::io {

namespace fs = std::filesystem;

void writeImage(const fs::path& path, const ImageF& image, bool dropAlpha) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    VEIL_CHECK(ext == ".png" || ext == ".exr", "cannot write '{}': use a .png or .exr name",
               path.string());
    VEIL_CHECK(image.width > 0 && image.height > 0 && image.channels > 0 &&
                   image.pixels.size() ==
                       static_cast<std::size_t>(image.width) * image.height * image.channels,
               "cannot write '{}': empty or inconsistent image", path.string());
    const int outChannels = (dropAlpha && image.channels == 4) ? 3 : image.channels;
    std::vector<float> data(static_cast<std::size_t>(image.width) * image.height * outChannels);
    for (std::size_t p = 0; p < static_cast<std::size_t>(image.width) * image.height; ++p)
        for (int c = 0; c < outChannels; ++c)
            data[p * outChannels + c] = image.pixels[p * image.channels + c];

    writeFileAtomically(path, [&](const fs::path& tmp) {
        auto out = OIIO::ImageOutput::create(tmp.string());
        VEIL_CHECK(out, "cannot write '{}': {}", path.string(), OIIO::geterror());
        OIIO::ImageSpec spec(image.width, image.height, outChannels,
                             ext == ".png" ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::HALF);
        if (ext == ".exr") spec.attribute("compression", "zip");
        VEIL_CHECK(out->open(tmp.string(), spec), "cannot write '{}': {}", path.string(),
                   out->geterror());
        // Half rounded to nearest here (base/half.h), not left to the library's conversion.
        std::vector<std::uint16_t> halves;
        if (ext == ".exr")
            for (float v : data)
                halves.push_back(floatToHalf(v));
        const bool ok = ext == ".exr" ? out->write_image(OIIO::TypeDesc::HALF, halves.data())
                                      : out->write_image(OIIO::TypeDesc::FLOAT, data.data());
        std::string err = out->geterror();
        // close() flushes the last compressed rows: its failure is a truncated file too.
        const bool closed = out->close();
        if (err.empty()) err = out->geterror();
        VEIL_CHECK(ok && closed, "cannot write '{}': {}", path.string(),
                   err.empty() ? "the image writer failed" : err);
    });
}

ImageF readImage(const fs::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    VEIL_CHECK(in, "cannot read image '{}': {}", path.string(), OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    ImageF image(spec.width, spec.height, spec.nchannels);
    const bool ok =
        in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data());
    const std::string err = in->geterror();
    in->close();
    VEIL_CHECK(ok, "cannot read image '{}': {}", path.string(), err);
    return image;
}

} // namespace veil::io
