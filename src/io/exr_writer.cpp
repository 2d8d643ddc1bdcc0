#include "io/exr_writer.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/half.h"

#include <OpenImageIO/imageio.h>

#include <cstdint>

namespace veil::io {

namespace fs = std::filesystem;

void writeExr(const fs::path& path, const ExrImage& image) {
    const int n = static_cast<int>(image.channels.size());
    VEIL_CHECK(image.width > 0 && image.height > 0 && n > 0 &&
                   image.pixels.size() == std::size_t(image.width) * image.height * n,
               "cannot write '{}': empty or inconsistent image", path.string());
    OIIO::ImageSpec spec(image.width, image.height, n,
                         image.half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
    spec.channelnames = image.channels;
    spec.alpha_channel = spec.channelindex("A");
    spec.z_channel = spec.channelindex("Z");
    spec.attribute("compression", "zip");
    for (const auto& [name, value] : image.strings)
        spec.attribute(name, value);
    for (const auto& [name, m] : image.matrices)
        spec.attribute(name, OIIO::TypeDesc::TypeMatrix44, m.data());
    std::vector<std::uint16_t> halves;
    if (image.half) {
        halves.resize(image.pixels.size());
        for (std::size_t i = 0; i < halves.size(); ++i)
            halves[i] = floatToHalf(image.pixels[i]);
    }
    writeFileAtomically(path, [&](const fs::path& tmp) {
        auto out = OIIO::ImageOutput::create(tmp.string());
        VEIL_CHECK(out, "cannot write '{}': {}", path.string(), OIIO::geterror());
        VEIL_CHECK(out->open(tmp.string(), spec), "cannot write '{}': {}", path.string(),
                   out->geterror());
        // Data already in the file's type: OpenImageIO copies it without converting.
        const bool ok = image.half ? out->write_image(OIIO::TypeDesc::HALF, halves.data())
                                   : out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data());
        std::string err = out->geterror();
        const bool closed = out->close(); // flushes the last compressed rows
        if (err.empty()) err = out->geterror();
        VEIL_CHECK(ok && closed, "cannot write '{}': {}", path.string(),
                   err.empty() ? "the image writer failed" : err);
    });
}

} // namespace veil::io
