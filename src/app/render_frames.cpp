// `veil render --frames` (render_frames.h): argument checks, signals, progress and the report;
// src/sequence renders the range and encodes the video.
#include "app/render_frames.h"

#include "app/cli_checks.h"
#include "app/shared_options.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/output_lock.h"
#include "base/process.h"
#include "base/progress.h"
#include "base/text.h"
#include "gpu/context.h"
#include "scene/scene.h"
#include "scene/scene_values.h"
#include "scene/timeline.h"
#include "sequence/range_render.h"
#include "sequence/video.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>

namespace veil::app {

namespace fs = std::filesystem;

namespace {

// --frames A-B[:S]: a malformed or too long range is a usage error.
scene::FrameRange usageFrameRange(const std::string& text) {
    try {
        return scene::parseFrameRange(text);
    } catch (const Error& e) {
        usageError(e.what());
    }
}

} // namespace

void runRenderFrames(const RenderFramesArgs& args) {
    if (!args.frames.empty() && args.frame) usageError("give --frames or --frame, not both");
    const std::string ext = lowerExtension(args.output);
    if (ext != ".png" && ext != ".exr" && ext != ".mp4")
        usageError(fmt::format("output '{}' must end in .png, .exr or .mp4", args.output));
    if (!args.report.empty() && lowerExtension(args.report) != ".json")
        usageError(fmt::format("report '{}' must end in .json", args.report));
    if (ext != ".exr" && args.half)
        usageError(fmt::format("--half needs an .exr output, not '{}'", args.output));
    const std::optional<scene::FrameRange> asked =
        args.frame            ? std::optional(scene::FrameRange{*args.frame, *args.frame, 1})
        : args.frames.empty() ? std::nullopt
                              : std::optional(usageFrameRange(args.frames));
    std::optional<fs::path> ffmpeg;
    if (ext == ".mp4") {
        if (args.resume) usageError("--resume is for numbered images, not a video");
        if (asked && asked->step != 1) usageError("a video needs consecutive frames (no :STEP)");
        ffmpeg = sequence::findFfmpeg();
        VEIL_CHECK(ffmpeg.has_value(),
                   "output '{}': writing video needs ffmpeg, which is not installed (Debian "
                   "package ffmpeg); write numbered images instead, e.g. -o frames.####.png",
                   args.output);
    } else if (asked && asked->count() > 1) {
        outputForFrame(args.output, asked->first, false, "output"); // a range needs a pattern
    }
    std::vector<fs::path> inputs{args.scene};
    if (!args.report.empty()) checkOutputPath(args.report, "report", inputs);

    const scene::AnimatedScene scene = scene::loadAnimatedScene(args.scene, args.overrides);
    const scene::FrameRange range = asked ? *asked : scene::sceneFrameRange(scene.timeline);
    const std::vector<int> frames = range.frames(
        asked ? "--frames"
              : fmt::format("the frames of '{}' (time.frame_range or its keys)", args.scene));
    // A camera key that makes a frame unrenderable fails before the first frame is written.
    for (int f : frames)
        try {
            scene::checkCamerasAtFrame(scene, f);
        } catch (const Error& e) {
            throw Error(fmt::format("{}: {}", args.scene, e.what()));
        }

    sequence::RangeJob job;
    job.scenePath = fs::absolute(args.scene);
    job.frames = frames;
    job.output = args.output;
    job.resume = args.resume;
    job.half = args.half;
    job.options =
        frame::RendererOptions{args.width, args.height, args.camera, args.oit, {}, args.shadows};
    job.stop = &process::StopOnSignal::stopFlag();
    // Every output path is checked before anything renders.
    if (ffmpeg) checkOutputPath(args.output, "output", inputs);
    for (int f : ffmpeg ? std::vector<int>{} : frames)
        checkOutputPath(outputForFrame(job.output, f, frames.size() == 1, "output"), "output",
                        inputs);
    // A second run writing one of these frames (or the video) now is refused: two runs at once
    // left frames of two sizes. Runs over other frames of the pattern go on (base/output_lock.h).
    const OutputLock lock(args.output, ffmpeg ? std::vector<int>{} : frames, "veil render");
    if (!scene.timeline.animated() && frames.size() > 1)
        std::fprintf(stderr,
                     "veil: warning: '%s' has no animation (no sequence, camera or light keys): "
                     "its %zu frames are identical\n",
                     args.scene.c_str(), frames.size());
    fs::path videoFolder;
    if (ffmpeg) {
        // A new folder of its own (mkdtemp), never one planted at a known name.
        std::string made =
            (fs::path(args.output).parent_path() /
             fmt::format(".{}.frames.XXXXXX", fs::path(args.output).filename().string()))
                .string();
        VEIL_CHECK(::mkdtemp(made.data()), "cannot create a folder for the frames of '{}': {}",
                   args.output, std::strerror(errno));
        videoFolder = made;
        job.output = (videoFolder / "%06d.png").string();
    }
    const bool showProgress = progressWanted(args.progress);
    const bool terminal = ::isatty(STDERR_FILENO) != 0;
    job.progress = [&](const sequence::RangeProgress& p) {
        if (!showProgress) return;
        std::fprintf(stderr, "%sveil: frame %d/%d (frame %d) %.2f frames/s, %.0f s left%s",
                     terminal ? "\r" : "", p.done, p.total, p.frame, p.framesPerSecond,
                     p.secondsLeft, terminal ? "\033[K" : "\n");
        std::fflush(stderr);
    };

    gpu::HeadlessContext context({args.device, args.glDebug});
    sequence::RangeResult result;
    {
        process::StopOnSignal signals;
        result = sequence::renderRange(scene, job, context.info());
    }
    if (showProgress && terminal) std::fprintf(stderr, "\n");
    int rendered = 0, skipped = 0;
    for (const auto& f : result.frames)
        (f.skipped ? skipped : rendered)++;
    if (!args.report.empty()) {
        nlohmann::json report = result.json();
        report["scene"] = fs::absolute(args.scene).string();
        report["output"] = fs::absolute(args.output).string();
        report["renderer"] = context.info().renderer;
        report["frame_range"] = {range.first, range.last, range.step};
        report["scene_values"] = scene::sceneValues(scene.scene);
        writeTextFileAtomically(args.report, report.dump(2) + "\n");
    }
    if (result.interrupted) {
        throw Error(fmt::format("interrupted by signal {}: {} frames written, {} skipped, {} not "
                                "rendered (complete frames only; --resume continues)",
                                process::StopOnSignal::signal(), rendered, skipped,
                                frames.size() - result.frames.size()));
    }
    if (ffmpeg) {
        sequence::encodeVideo(*ffmpeg, videoFolder / "%06d.png", frames.front(),
                              scene.timeline.time.fps, args.output);
        fs::remove_all(videoFolder);
    }
    std::cout << fmt::format("wrote {} frame{}{} ({}-{}:{}) to {} in {:.2f} s ({})\n", rendered,
                             rendered == 1 ? "" : "s",
                             skipped ? fmt::format(", skipped {} complete", skipped) : "",
                             range.first, range.last, range.step, args.output, result.wallSeconds,
                             context.info().renderer);
    if (!args.report.empty()) std::cout << "wrote " << args.report << " (per-frame times)\n";
}

} // namespace veil::app
