#include "io/image_io.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/half.h"
#include "io/provenance.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <string>

#include <sys/statvfs.h>
#include <unistd.h>

namespace veil::io {

namespace fs = std::filesystem;

std::string describeWriteFailure(const fs::path& path, const std::string& libraryError,
                                 int savedErrno) {
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    bool full = savedErrno == ENOSPC || savedErrno == EDQUOT;
    struct statvfs st {};
    if (!full && ::statvfs(dir.c_str(), &st) == 0 && st.f_blocks > 0)
        full = (::geteuid() == 0 ? st.f_bfree : st.f_bavail) == 0;
    std::string library = libraryError;
    for (char& c : library)
        if (c == '\n' || c == '\r') c = ' ';
    if (full)
        return fmt::format("cannot write '{}': no space left on device (the file system holding "
                           "'{}' is full{})",
                           path.string(), dir.string(), library.empty() ? "" : "; " + library);
    return fmt::format("cannot write '{}': {}", path.string(),
                       library.empty() ? std::string("the image writer failed") : library);
}

void writeImage(const fs::path& path, const ImageF& image, bool dropAlpha,
                const std::vector<std::pair<std::string, std::string>>& attributes) {
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
        for (const auto& [name, value] : provenanceAttributes())
            spec.attribute(name, value);
        for (const auto& [name, value] : attributes)
            spec.attribute(name, value);
        errno = 0;
        if (!out->open(tmp.string(), spec))
            throw Error(describeWriteFailure(path, out->geterror(), errno));
        // Half rounded to nearest here (base/half.h), not left to the library's conversion.
        std::vector<std::uint16_t> halves;
        if (ext == ".exr")
            for (float v : data)
                halves.push_back(floatToHalf(v));
        const bool ok = ext == ".exr" ? out->write_image(OIIO::TypeDesc::HALF, halves.data())
                                      : out->write_image(OIIO::TypeDesc::FLOAT, data.data());
        int savedErrno = errno;
        std::string err = out->geterror();
        // close() flushes the last compressed rows: its failure is a truncated file too.
        const bool closed = out->close();
        if (ok) savedErrno = errno;
        if (err.empty()) err = out->geterror();
        if (!ok || !closed) throw Error(describeWriteFailure(path, err, savedErrno));
    });
}

namespace {

// Codec libraries under OpenImageIO print on stderr themselves (libpng: "libpng error: IDAT:
// CRC error"), before and beside Veil's one error line. While it lives, this sends file
// descriptor 2 to a temporary file; text() is what was printed, on one line.
class StderrCapture {
public:
    StderrCapture() {
        std::fflush(stderr);
        file_ = std::tmpfile();
        saved_ = file_ ? dup(STDERR_FILENO) : -1;
        if (saved_ >= 0 && dup2(fileno(file_), STDERR_FILENO) < 0) {
            close(saved_);
            saved_ = -1;
        }
    }
    StderrCapture(const StderrCapture&) = delete;
    StderrCapture& operator=(const StderrCapture&) = delete;
    ~StderrCapture() {
        restore();
        if (file_) std::fclose(file_);
    }
    std::string text() {
        restore();
        std::string out;
        if (!file_) return out;
        std::rewind(file_);
        char buf[512];
        for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, file_)) > 0 && out.size() < 2000;)
            out.append(buf, n);
        for (char& c : out)
            if (c == '\n' || c == '\r') c = ' ';
        while (!out.empty() && out.back() == ' ')
            out.pop_back();
        return out;
    }

private:
    void restore() {
        if (saved_ < 0) return;
        std::fflush(stderr);
        dup2(saved_, STDERR_FILENO);
        close(saved_);
        saved_ = -1;
    }
    std::FILE* file_ = nullptr;
    int saved_ = -1;
};

} // namespace

void checkReadableFile(const fs::path& path, const char* what) {
    // /dev/zero or a FIFO would be read forever (scene files refuse them the same way): only
    // regular files (or links to them) are opened.
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    VEIL_CHECK(!fs::is_directory(st), "cannot read {} '{}': it is a folder, not a file", what,
               path.string());
    VEIL_CHECK(!fs::exists(st) || fs::is_regular_file(st),
               "cannot read {} '{}': not a regular file (a device, FIFO or socket)", what,
               path.string());
}

ImageF readImage(const fs::path& path) {
    checkReadableFile(path, "image");
    StderrCapture codec;
    const auto failed = [&](const std::string& err) {
        const std::string printed = codec.text();
        return Error(fmt::format("cannot read image '{}': {}{}", path.string(), err,
                                 printed.empty() ? "" : " (" + printed + ")"));
    };
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) throw failed(OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    ImageF image(spec.width, spec.height, spec.nchannels);
    const bool ok =
        in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data());
    const std::string err = in->geterror();
    in->close();
    if (!ok) throw failed(err);
    return image;
}

std::vector<std::pair<std::string, std::string>> readImageAttributes(const fs::path& path) {
    checkReadableFile(path, "image");
    StderrCapture codec;
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) {
        const std::string printed = codec.text();
        throw Error(fmt::format("cannot read image '{}': {}{}", path.string(), OIIO::geterror(),
                                printed.empty() ? "" : " (" + printed + ")"));
    }
    std::vector<std::pair<std::string, std::string>> out;
    for (const OIIO::ParamValue& p : in->spec().extra_attribs)
        if (p.type() == OIIO::TypeDesc::STRING) out.emplace_back(p.name().string(), p.get_string());
    in->close();
    return out;
}

} // namespace veil::io
