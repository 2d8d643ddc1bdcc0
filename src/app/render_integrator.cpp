#include "app/render_integrator.h"

#include "base/progress.h"
#include "integrators/registry.h"
#include "io/image_io.h"
#include "io/metrics.h"

#include <fmt/format.h>

#include <chrono>
#include <iostream>

namespace veil::app {

namespace fs = std::filesystem;

fs::path standardErrorPath(const fs::path& output) {
    return output.parent_path() / (output.stem().string() + "-stderr.exr");
}

void renderWithIntegrator(const scene::Scene& scene, const std::string& integrator,
                          const std::string& camera, int width, int height, const fs::path& output,
                          bool progress) {
    const volume::IntegratorInfo& info =
        volume::IntegratorRegistry::instance().get(integrator, "--integrator");
    const int w = width > 0 ? width : scene.render.width;
    const int h = height > 0 ? height : scene.render.height;
    const auto start = std::chrono::steady_clock::now();
    volume::IntegratorImage image;
    {
        ProgressTicker ticker(integrator == "pathtraced" ? std::string("path tracing")
                                                         : "integrating (" + integrator + ")",
                              progressWanted(progress));
        image = info.render(scene, scene.camera(camera), w, h, [](int) { return true; });
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // Both files are complete before either is renamed into place by writeImage.
    const bool png = output.extension() == ".png" || output.extension() == ".PNG";
    // PNG: the frame's tone map on the CPU (exposure, then [Narkowicz16]'s ACES fit or a clamp,
    // then sRGB).
    const metrics::ToneMap op =
        scene.render.tonemap == "aces" ? metrics::ToneMap::Aces : metrics::ToneMap::Clamp;
    io::writeImage(output, png ? metrics::toneMapSrgb(image.radiance, scene.render.exposure, op)
                               : image.radiance);
    const bool monteCarlo = !image.standardError.pixels.empty();
    if (monteCarlo) io::writeImage(standardErrorPath(output), image.standardError);
    if (!scene.objects.empty())
        std::cout << fmt::format("note: the {} image has the volumes only; the scene's {} "
                                 "object(s) are not in it\n",
                                 integrator, scene.objects.size());
    std::cout << "wrote " << output.string() << " (" << w << "x" << h << ", " << integrator << ", "
              << image.samples << " spp, " << fmt::format("{:.1f}", seconds) << " s)\n";
    if (!monteCarlo) return;
    double meanError = 0.0, meanRadiance = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                meanError += image.standardError.at(x, y, c);
                meanRadiance += image.radiance.at(x, y, c);
            }
    std::cout << "wrote " << standardErrorPath(output).string()
              << fmt::format(" (per-pixel standard error; mean {:.3g} for a mean radiance of "
                             "{:.3g})\n",
                             meanError / (3.0 * w * h), meanRadiance / (3.0 * w * h));
}

} // namespace veil::app
