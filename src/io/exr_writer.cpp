#include "io/exr_writer.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/half.h"
#include "io/image_io.h"
#include "io/provenance.h"

#include <OpenImageIO/imageio.h>

#include <cerrno>
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
    for (const auto& [name, value] : provenanceAttributes())
        spec.attribute(name, value);
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
        errno = 0;
        if (!out->open(tmp.string(), spec))
            throw Error(describeWriteFailure(path, out->geterror(), errno));
        // Data already in the file's type: OpenImageIO copies it without converting.
        const bool ok = image.half ? out->write_image(OIIO::TypeDesc::HALF, halves.data())
                                   : out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data());
        int savedErrno = errno;
        std::string err = out->geterror();
        const bool closed = out->close(); // flushes the last compressed rows
        if (ok) savedErrno = errno;
        if (err.empty()) err = out->geterror();
        if (!ok || !closed) throw Error(describeWriteFailure(path, err, savedErrno));
    });
}

} // namespace veil::io
