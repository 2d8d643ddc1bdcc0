// veil.read_image, write_image, compare, heat_map, tonemap: src/io through NumPy arrays.
#include "bindings.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "io/exr_writer.h"
#include "io/image_io.h"
#include "io/metrics.h"

#include <fmt/ranges.h>
#include <pybind11/stl.h>

namespace veil::python {

namespace fs = std::filesystem;

namespace {

// An image file to read: it must exist (veil.FileNotFoundError) and be a regular file
// (/dev/zero or a FIFO would be read forever).
fs::path imageFile(py::handle value, const std::string& what) {
    const fs::path path = toPath(value, what);
    std::error_code ec;
    const auto status = fs::status(path, ec);
    if (!fs::exists(status))
        throw PyError(
            ErrorKind::FileNotFound,
            fmt::format("{}: image '{}' does not exist", what, printable(path.string(), 500)),
            path.string());
    VEIL_PY_CHECK(ErrorKind::Value, fs::is_regular_file(status),
                  "{}: image '{}' is not a regular file", what, printable(path.string(), 500));
    return path;
}

// An array, or a path read through OpenImageIO; RGB or RGBA needed for metrics.
ImageF imageArgument(py::handle value, const char* what) {
    ImageF img;
    if (isPathLike(value)) {
        const fs::path path = imageFile(value, what);
        img = classified(ErrorKind::Value, [&] { return io::readImage(path); });
        VEIL_PY_CHECK(ErrorKind::Value, img.channels >= 3,
                      "{}: '{}' has {} channel(s): RGB or RGBA needed", what,
                      printable(path.string(), 500), img.channels);
    } else {
        img = fromArray(value, what);
        VEIL_PY_CHECK(ErrorKind::Value, img.channels >= 3, "{}: {} channel(s): RGB or RGBA needed",
                      what, img.channels);
    }
    return img;
}

double exposureArgument(py::handle value) {
    const double exposure = toFloat(value, "exposure");
    VEIL_PY_CHECK(ErrorKind::Value, std::isfinite(exposure) && exposure > 0.0,
                  "exposure={} must be a finite number > 0", exposure);
    return exposure;
}

void checkSameSize(const ImageF& a, const ImageF& b) {
    VEIL_PY_CHECK(ErrorKind::Value, a.width == b.width && a.height == b.height,
                  "image is {}x{} but reference is {}x{}: cannot compare", a.width, a.height,
                  b.width, b.height);
}

metrics::ToneMap toneMapArgument(py::handle value, const char* what) {
    const std::string name = toStr(value, what);
    VEIL_PY_CHECK(ErrorKind::Value, name == "clamp" || name == "aces", "{}='{}': use clamp or aces",
                  what, printable(name, 100));
    return name == "aces" ? metrics::ToneMap::Aces : metrics::ToneMap::Clamp;
}

py::object compare(const ImageArg& image, const ImageArg& reference, const MetricArg& metric,
                   const FloatArg& exposureArg, const StrArg& tonemap) {
    const bool single = py::isinstance<py::str>(metric);
    const std::vector<std::string> known = metrics::metricNames();
    if (!single && !py::isinstance<py::list>(metric) && !py::isinstance<py::tuple>(metric))
        throw PyError(ErrorKind::Type,
                      fmt::format("metric: expected a metric name ({}) or a list of them, got {}",
                                  fmt::join(known, ", "), typeName(metric)));
    const std::vector<std::string> names = toStrList(metric, "metric", true);
    VEIL_PY_CHECK(ErrorKind::Value, !names.empty(), "metric: an empty list (known: {})",
                  fmt::join(known, ", "));
    for (const std::string& n : names)
        VEIL_PY_CHECK(ErrorKind::Value, metrics::isMetricName(n),
                      "metric: unknown metric '{}' (known: {})", printable(n, 100),
                      fmt::join(known, ", "));
    const double exposure = exposureArgument(exposureArg);
    const metrics::ToneMap op = toneMapArgument(tonemap, "tonemap");
    const ImageF a = imageArgument(image, "image");
    const ImageF b = imageArgument(reference, "reference");
    checkSameSize(a, b);
    py::dict out;
    for (const std::string& n : names) {
        const double v = metrics::compute(n, a, b, exposure, op);
        if (single) return py::float_(v);
        out[py::str(n)] = v;
    }
    return out;
}

void writeImage(const PathArg& pathArg, const ArrayArg& array, const BoolArg& halfArg) {
    const fs::path path = toPath(pathArg, "write_image(path)");
    const bool half = toBool(halfArg, "half");
    const std::string ext = lowerExtension(path.string());
    VEIL_PY_CHECK(ErrorKind::Value, ext == ".png" || ext == ".exr",
                  "write_image(path): '{}' must end in .png or .exr",
                  printable(path.string(), 500));
    classified(ErrorKind::Value, [&] { checkOutputPath(path, "output", {}); });
    ImageF img = fromArray(array, "write_image(image)");
    if (ext == ".png") {
        io::writeImage(path, img, false);
        return;
    }
    static const std::vector<std::vector<std::string>> names = {
        {"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
    io::ExrImage exr;
    exr.width = img.width;
    exr.height = img.height;
    exr.channels = names[std::size_t(img.channels - 1)];
    exr.pixels = std::move(img.pixels);
    exr.half = half;
    io::writeExr(path, exr);
}

} // namespace

void bindImages(py::module_& m) {
    m.def(
        "read_image",
        [](const PathArg& path) {
            const fs::path p = imageFile(path, "read_image(path)");
            return toArray(classified(ErrorKind::Value, [&] { return io::readImage(p); }));
        },
        py::arg("path"),
        R"doc(Read an image (EXR, PNG, anything OpenImageIO reads) as float32.

Returns H x W x C (H x W for one channel), row 0 at the top; 8-bit files come
back in [0, 1]. Channels in file order (EXR: R, G, B, A first).)doc");
    m.def("write_image", &writeImage, py::arg("path"), py::arg("image"), py::arg("half") = false,
          R"doc(Write an H x W or H x W x C (C = 1..4) array, atomically (a temporary file renamed).

.exr: linear values, float32 channels Y / Y,A / R,G,B / R,G,B,A (half=True:
half floats rounded to nearest). .png: 8-bit, values already display-encoded in
[0, 1] (use tonemap() for radiance).)doc");
    m.def(
        "compare", &compare, py::arg("image"), py::arg("reference"), py::arg("metric") = "rmse",
        py::arg("exposure") = 1.0, py::arg("tonemap") = "clamp",
        R"doc(Image error of `image` against `reference` (arrays or image files), as `veil compare`.

metric: rmse, maxabs, relmse, p99, psnr, ssim, nrmse (src/io/metrics.h has the
definitions), or a list of them (then a dict name -> value is returned). Metrics
use the RGB channels of linear images; ssim tone-maps both first (exposure,
tonemap 'clamp' or 'aces').)doc");
    m.def(
        "heat_map",
        [](const ImageArg& a, const ImageArg& b, const FloatArg& scaleArg) {
            const double scale = toFloat(scaleArg, "scale");
            VEIL_PY_CHECK(ErrorKind::Value, std::isfinite(scale) && scale >= 0.0,
                          "scale={}: expected a finite number >= 0 (the error shown white; 0: the "
                          "largest error)",
                          scale);
            const ImageF x = imageArgument(a, "image"), y = imageArgument(b, "reference");
            checkSameSize(x, y);
            return toArray(metrics::heatMap(x, y, scale));
        },
        py::arg("image"), py::arg("reference"), py::arg("scale") = 0.0,
        R"doc(Heat map of max |a - b| over RGB (H x W x 3 in [0, 1], for a PNG).

Black 0, through blue, red and yellow to white at `scale` (0: the largest error).)doc");
    m.def(
        "tonemap",
        [](const ImageArg& hdr, const FloatArg& exposureArg, const StrArg& op) {
            const double exposure = exposureArgument(exposureArg);
            const metrics::ToneMap t = toneMapArgument(op, "op");
            const ImageF img = imageArgument(hdr, "image");
            return toArray(metrics::toneMapSrgb(img, exposure, t));
        },
        py::arg("image"), py::arg("exposure") = 1.0, py::arg("op") = "clamp",
        "Linear radiance to sRGB display values in [0, 1] (x exposure, then clamp or the ACES "
        "fit, then the sRGB curve), H x W x 3.");
}

} // namespace veil::python
