// Frame ranges into numbered images (range_render.h).
#include "sequence/range_render.h"

#include "base/error.h"
#include "capture/frame_output.h"
#include "frame/renderer.h"
#include "grid/grid_preload.h"
#include "io/image_io.h"
#include "scene/timeline.h"
#include "sequence/range_player.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <memory>

namespace veil::sequence {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

std::string lowerExt(const fs::path& p) {
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
    return e;
}

} // namespace

fs::path outputFor(const std::string& output, int frame, bool single) {
    const std::optional<scene::FilePattern> pattern = scene::parseFilePattern(output);
    if (!pattern) {
        VEIL_CHECK(single,
                   "output '{}' has no frame pattern for a range of frames (write it as "
                   "name.####.exr, name.%04d.png, name.$F4.exr or name.#.png)",
                   output);
        return output;
    }
    return pattern->fileFor(frame);
}

bool outputComplete(const fs::path& path, int width, int height) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return false;
    try {
        const ImageF image = io::readImage(path);
        return image.width == width && image.height == height;
    } catch (const std::exception&) {
        return false;
    }
}

nlohmann::json RangeResult::json() const {
    nlohmann::json frameList = nlohmann::json::array();
    for (const FrameTimes& f : frames) {
        nlohmann::json j;
        if (f.skipped) {
            j = {{"frame", f.frame}, {"skipped", "complete already (--resume)"}};
        } else {
            j = f.json();
            j.update({{"gpu_ms", f.gpuMs}, {"write_ms", f.writeMs}});
        }
        j["output"] = f.output.string();
        frameList.push_back(std::move(j));
    }
    return {{"frames", frameList},
            {"interrupted", interrupted},
            {"wall_s", wallSeconds},
            {"peak_read_ahead_bytes", peakReadAheadBytes},
            {"times", "read_ms, convert_ms on a worker thread, overlapping earlier frames; "
                      "wait_ms: the render thread waiting for them; setup_ms: the renderer "
                      "built (first frame, or a frame of another structure, with its upload) "
                      "or the camera and lights switched; upload_ms: the frame's volume "
                      "uploads, made while the previous frame rendered when uploaded_ahead; "
                      "render_ms: render() to glFinish; ahead_ms: taking and uploading the "
                      "next frame while this one renders"}};
}

RangeResult renderRange(const scene::AnimatedScene& scene, const RangeJob& job,
                        const gpu::ContextInfo& context) {
    VEIL_CHECK(!job.frames.empty(), "no frames to render");
    const bool single = job.frames.size() == 1;
    const std::string ext = lowerExt(job.output);
    VEIL_CHECK(ext == ".png" || ext == ".exr", "output '{}' must end in .png or .exr", job.output);
    // Every frame's files exist (or are held) before the first frame renders.
    for (int f : job.frames)
        scene::volumeFrames(scene, f);

    const auto start = Clock::now();
    RangeResult result;
    std::vector<int> todo;
    const int width = job.options.width > 0 ? job.options.width : scene.scene.render.width;
    const int height = job.options.height > 0 ? job.options.height : scene.scene.render.height;
    for (int f : job.frames) {
        const fs::path out = outputFor(job.output, f, single);
        if (job.resume && outputComplete(out, width, height)) {
            FrameTimes t;
            t.frame = f;
            t.output = out;
            t.skipped = true;
            result.frames.push_back(std::move(t));
        } else {
            todo.push_back(f);
        }
    }
    RangeProgress progress;
    progress.total = int(job.frames.size());
    progress.done = int(result.frames.size());
    if (todo.empty()) return result;

    GLint max3D = 0; // the workers convert the grids for this GPU
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    RangePlayer player(scene, todo, context, job.options,
                       std::size_t(scene.timeline.time.prefetchBudgetMiB) << 20, job.threads,
                       max3D);
    const auto renderStart = Clock::now();
    int rendered = 0;
    for (std::size_t i = 0; i < todo.size(); ++i) {
        if (job.stop && job.stop->load()) {
            result.interrupted = true;
            break;
        }
        const PlayedFrame played = player.step();
        FrameTimes t;
        static_cast<FrameStages&>(t) = played;
        t.output = outputFor(job.output, played.frame, single);
        const frame::Renderer* renderer = played.renderer;
        for (const auto& pass : renderer->passTimes())
            t.gpuMs += pass.milliseconds;

        const auto mark = Clock::now();
        capture::writeFrame(t.output, *renderer,
                            {job.scenePath,
                             context.renderer,
                             job.half,
                             {{"veil:frame", std::to_string(played.frame)}}});
        t.writeMs = msSince(mark);
        result.frames.push_back(std::move(t));
        ++rendered;

        progress.done++;
        progress.frame = played.frame;
        const double elapsed = std::chrono::duration<double>(Clock::now() - renderStart).count();
        progress.framesPerSecond = rendered / std::max(elapsed, 1e-9);
        progress.secondsLeft = double(todo.size() - i - 1) / progress.framesPerSecond;
        if (job.progress) job.progress(progress);
    }
    result.peakReadAheadBytes = player.peakReadAheadBytes();
    result.wallSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
}

} // namespace veil::sequence
