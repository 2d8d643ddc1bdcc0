#include "app/render_pathtraced.h"

#include "app/progress.h"
#include "compare/target.h"

#include "io/image_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>

namespace veil::app {

namespace fs = std::filesystem;

namespace {

// The frame's tone map on the CPU (exposure, then Narkowicz's ACES fit [Narkowicz16] or a
// clamp, then the sRGB transfer function), for PNG output.
ImageF toneMap(const ImageF& hdr, const scene::RenderSettings& r) {
    ImageF out(hdr.width, hdr.height, 3);
    for (int y = 0; y < hdr.height; ++y)
        for (int x = 0; x < hdr.width; ++x)
            for (int c = 0; c < 3; ++c) {
                double v = std::max(0.0, double(hdr.at(x, y, c)) * r.exposure);
                if (r.tonemap == "aces")
                    v = (v * (2.51 * v + 0.03)) / (v * (2.43 * v + 0.59) + 0.14);
                v = std::clamp(v, 0.0, 1.0);
                v = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
                out.at(x, y, c) = float(v);
            }
    return out;
}

} // namespace

fs::path pathTracedErrorPath(const fs::path& output) {
    return output.parent_path() / (output.stem().string() + "-stderr.exr");
}

void renderPathTraced(const scene::Scene& scene, const volume::PathTracerSettings& settings,
                      const std::string& camera, int width, int height, const fs::path& output,
                      bool progress) {
    const int w = width > 0 ? width : scene.render.width;
    const int h = height > 0 ? height : scene.render.height;
    std::string note;
    const auto start = std::chrono::steady_clock::now();
    volume::PathTracedImage image;
    {
        ProgressTicker ticker("path tracing", progressWanted(progress));
        image = compare::pathTracedReference(scene, settings, camera, w, h, note);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // Both files are complete before either is renamed into place by writeImage.
    const bool png = output.extension() == ".png" || output.extension() == ".PNG";
    io::writeImage(output, png ? toneMap(image.radiance, scene.render) : image.radiance);
    const fs::path errorPath = pathTracedErrorPath(output);
    io::writeImage(errorPath, image.standardError);
    double meanError = 0.0, meanRadiance = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                meanError += image.standardError.at(x, y, c);
                meanRadiance += image.radiance.at(x, y, c);
            }
    if (!note.empty()) std::cout << note << "\n";
    std::cout << "wrote " << output.string() << " (" << w << "x" << h << ", path traced, "
              << image.samples << " spp, " << fmt::format("{:.1f}", seconds) << " s)\n"
              << "wrote " << errorPath.string()
              << fmt::format(" (per-pixel standard error; mean {:.3g} for a mean radiance of "
                             "{:.3g})\n",
                             meanError / (3.0 * w * h), meanRadiance / (3.0 * w * h));
}

} // namespace veil::app
