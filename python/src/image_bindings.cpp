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

// An array, or a path read through OpenImageIO; RGB or RGBA needed for metrics.
ImageF imageArgument(py::handle value, const char* what) {
    ImageF img;
    if (isPathLike(value)) {
        const fs::path path = toPath(value, what);
        VEIL_CHECK(fs::exists(path), "{} '{}' does not exist", what, printable(path.string(), 500));
        img = io::readImage(path);
        VEIL_CHECK(img.channels >= 3, "{} '{}' has {} channel(s): RGB or RGBA needed", what,
                   printable(path.string(), 500), img.channels);
    } else {
        img = fromArray(value, what);
        VEIL_CHECK(img.channels >= 3, "{}: {} channel(s): RGB or RGBA needed", what, img.channels);
    }
    return img;
}

void checkSameSize(const ImageF& a, const ImageF& b) {
    VEIL_CHECK(a.width == b.width && a.height == b.height,
               "image is {}x{} but reference is {}x{}: cannot compare", a.width, a.height, b.width,
               b.height);
}

metrics::ToneMap toneMapArgument(const std::string& name) {
    VEIL_CHECK(name == "clamp" || name == "aces", "tonemap '{}': use clamp or aces",
               printable(name, 100));
    return name == "aces" ? metrics::ToneMap::Aces : metrics::ToneMap::Clamp;
}

py::object compare(py::handle image, py::handle reference, py::handle metric, double exposure,
                   const std::string& tonemap) {
    const bool single = py::isinstance<py::str>(metric);
    std::vector<std::string> names;
    if (single)
        names.push_back(metric.cast<std::string>());
    else
        names = metric.cast<std::vector<std::string>>();
    for (const std::string& n : names)
        VEIL_CHECK(metrics::isMetricName(n), "metric: unknown metric '{}' (known: {})",
                   printable(n, 100), fmt::join(metrics::metricNames(), ", "));
    VEIL_CHECK(std::isfinite(exposure) && exposure > 0.0, "exposure {} must be > 0", exposure);
    const metrics::ToneMap op = toneMapArgument(tonemap);
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

void writeImage(py::handle pathArg, py::handle array, bool half) {
    const fs::path path = toPath(pathArg, "write_image");
    const std::string ext = lowerExtension(path.string());
    VEIL_CHECK(ext == ".png" || ext == ".exr", "output '{}' must end in .png or .exr",
               printable(path.string(), 500));
    checkOutputPath(path, "output", {});
    ImageF img = fromArray(array, "write_image");
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
        [](py::object path) {
            const fs::path p = toPath(path, "read_image");
            VEIL_CHECK(fs::exists(p), "image '{}' does not exist", printable(p.string(), 500));
            return toArray(io::readImage(p));
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
        [](py::handle a, py::handle b, double scale) {
            const ImageF x = imageArgument(a, "image"), y = imageArgument(b, "reference");
            checkSameSize(x, y);
            return toArray(metrics::heatMap(x, y, scale));
        },
        py::arg("image"), py::arg("reference"), py::arg("scale") = 0.0,
        R"doc(Heat map of max |a - b| over RGB (H x W x 3 in [0, 1], for a PNG).

Black 0, through blue, red and yellow to white at `scale` (0: the largest error).)doc");
    m.def(
        "tonemap",
        [](py::handle hdr, double exposure, const std::string& op) {
            VEIL_CHECK(std::isfinite(exposure) && exposure > 0.0, "exposure {} must be > 0",
                       exposure);
            const metrics::ToneMap t = toneMapArgument(op);
            const ImageF img = imageArgument(hdr, "image");
            return toArray(metrics::toneMapSrgb(img, exposure, t));
        },
        py::arg("image"), py::arg("exposure") = 1.0, py::arg("op") = "clamp",
        "Linear radiance to sRGB display values in [0, 1] (x exposure, then clamp or the ACES "
        "fit, then the sRGB curve), H x W x 3.");
}

} // namespace veil::python
