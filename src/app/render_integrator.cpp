#include "app/render_integrator.h"

#include "base/error.h"
#include "base/progress.h"
#include "integrators/medium.h"
#include "integrators/path_tracer.h"
#include "integrators/registry.h"
#include "io/image_io.h"
#include "io/metrics.h"

#include <fmt/format.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <mutex>
#include <thread>

namespace veil::app {

namespace fs = std::filesystem;

fs::path standardErrorPath(const fs::path& output) {
    return output.parent_path() / (output.stem().string() + "-stderr.exr");
}

namespace {

// "45 s", "3.2 h", "19 days".
std::string duration(double seconds) {
    if (seconds < 120.0) return fmt::format("{:.0f} s", seconds);
    if (seconds < 7200.0) return fmt::format("{:.0f} min", seconds / 60.0);
    if (seconds < 172800.0) return fmt::format("{:.1f} h", seconds / 3600.0);
    return fmt::format("{:.0f} days", seconds / 86400.0);
}

std::string refusal(int w, int h, const volume::PathTracerSettings& s, double estimate,
                    const std::string& how, double limit) {
    return fmt::format("path tracing {}x{} at {} spp (max_bounces {}) would take about {} ({}), "
                       "over --time-limit {:g} s: lower render.pathtraced.spp, "
                       "render.pathtraced.max_bounces or the image size, or raise --time-limit "
                       "(0 = no limit)",
                       w, h, s.spp, s.maxBounces, duration(estimate), how, limit);
}

// The path tracer with an estimate before it starts: one sample through each of up to 64
// pixels spread over the image, timed, scaled to spp x pixels over the threads; refused past
// `timeLimit` seconds. The timed samples run on their own thread: while they run, the time so
// far over the samples done (+1 for the one running) bounds the rate from below, so even a
// single sample that would run for hours (max_bounces 1048576 in a dense white medium) is
// refused once that bound passes the limit. Each pass then measures the rate again (refused
// when the measured estimate passes the limit) and shows "N spp, k %, about t s left".
volume::IntegratorImage pathTrace(const scene::Scene& scene, const scene::Camera& camera, int w,
                                  int h, double timeLimit) {
    using Clock = std::chrono::steady_clock;
    const volume::PathTracerSettings settings = volume::pathTracerSettings(scene);
    const auto tracer = std::make_shared<const volume::VolumePathTracer>(
        scene, volume::loadMediumGrids(scene), settings);
    const int threads = std::max(1, tbb::this_task_arena::max_concurrency());
    const double samples = double(settings.spp) * w * h;
    const int pilot = std::min(64, w * h);
    struct Pilot {
        std::atomic<int> done{0};
        std::mutex mutex;
        std::condition_variable finished;
    };
    const auto state = std::make_shared<Pilot>();
    const auto start = Clock::now();
    std::thread([tracer, state, camera, w, h, pilot] {
        for (int k = 0; k < pilot; ++k) {
            const long long i = (long long)k * w * h / pilot;
            tracer->sample(camera, w, h, int(i % w) + 0.5, int(i / w) + 0.5, std::uint64_t(i), 0u);
            state->done = k + 1;
        }
        std::lock_guard lock(state->mutex);
        state->finished.notify_all();
    }).detach();
    for (;;) {
        {
            std::unique_lock lock(state->mutex);
            state->finished.wait_for(lock, std::chrono::milliseconds(200),
                                     [&] { return state->done == pilot; });
        }
        const int done = state->done;
        const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
        const double perSample = elapsed / (done == pilot ? pilot : done + 1);
        const double estimate = perSample * samples / threads;
        if (timeLimit > 0.0 && estimate > timeLimit) {
            const std::string message = refusal(
                w, h, settings, estimate,
                done == pilot
                    ? fmt::format("{:.3g} s per sample measured over {} pixels, {} threads",
                                  perSample, pilot, threads)
                    : fmt::format("at least {:.3g} s per sample: {} of {} timed samples done "
                                  "in {:.1f} s",
                                  perSample, done, pilot, elapsed),
                timeLimit);
            if (done == pilot) throw Error(message);
            // The timed sample still runs on its thread and cannot be stopped: the process
            // ends here, having written nothing.
            std::fprintf(stderr, "veil: error: %s\n", message.c_str());
            std::fflush(stderr);
            std::_Exit(1);
        }
        if (done == pilot) break;
    }
    ProgressNote note(fmt::format("{} spp", settings.spp));
    bool over = false;
    double measured = 0.0;
    const auto renderStart = Clock::now();
    volume::PathTracedImage image = tracer->render(camera, w, h, [&](int done) {
        const double elapsed = std::chrono::duration<double>(Clock::now() - renderStart).count();
        measured = elapsed / done * settings.spp;
        note.set(double(done) / settings.spp);
        over = timeLimit > 0.0 && measured > timeLimit && done < settings.spp;
        return !over;
    });
    if (over)
        throw Error(refusal(w, h, settings, measured,
                            fmt::format("measured over the first {} spp", image.samples),
                            timeLimit));
    return {std::move(image.radiance), std::move(image.standardError), image.samples};
}

} // namespace

void renderWithIntegrator(const scene::Scene& scene, const std::string& integrator,
                          const std::string& camera, int width, int height, const fs::path& output,
                          bool progress, double timeLimit) {
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
        image = integrator == "pathtraced"
                    ? pathTrace(scene, scene.camera(camera), w, h, timeLimit)
                    : info.render(scene, scene.camera(camera), w, h, [](int) { return true; });
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
