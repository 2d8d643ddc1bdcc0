// veil-seqbench: plays a scene's frame range the way `veil render --frames` does, without
// writing images, and measures where a frame's time goes. Worker threads read and convert the
// next frames (sequence/prefetch.h; the conversion itself multithreaded with TBB) while the
// render thread renders the current one and, behind its render, uploads the next frame's
// volumes (sequence/range_player.h). Reported per frame (median, mean):
//   read_ms, convert_ms  on a worker, overlapping earlier frames;
//   wait_ms              the render thread waiting for the workers;
//   setup_ms             the frame's renderer (sequence/prefetch.h RangeRenderer: built for
//                        the first frame, then the camera and lights switched; with
//                        --serial-upload also the upload of its volumes);
//   upload_ms            the frame's volume upload calls (staging buffer, texture copies
//                        queued), made during the previous frame's render unless
//                        --serial-upload; uploaded_mb its bytes;
//   render_ms            render() to glFinish, without the next frame's upload calls;
//   ahead_ms             taking and uploading the next frame while the GPU renders;
//   frame_ms             one frame's whole time on the render thread.
// end to end: frames / wall seconds of the whole loop. --scrub-back N then shows the N frames
// before the range's last one again, last first (as the viewer's timeline scrubbing back),
// reported under "scrub_back" with the same fields and the number of volume uploads (0 when
// the frames are held on the GPU: render.sequence_gpu_cache_mib, "gpu_frames"). Then, on
// the distinct frames alone: the upload of a frame's conversion into new textures (GpuVolume,
// glFinish) and into the textures of the previous distinct frame (GpuVolume::replace, as a
// range's frames upload; only frames after the first), and the CPU conversion cost per
// million active voxels with all threads and with one. Links the core only (no OpenImageIO,
// no VTK), like veil-bench. bench/run.py runs it for the sequence-playback set.
#include "base/atomic_file.h"
#include "base/error.h"
#include "fog/fog_pass.h"
#include "fog/gpu_volume.h"
#include "frame/renderer.h"
#include "gpu/context.h"
#include "grid/density_grid.h"
#include "grid/grid_preload.h"
#include "scene/timeline.h"
#include "sequence/prefetch.h"
#include "sequence/range_player.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>
#include <set>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

void usage() {
    std::puts("usage: veil-seqbench <scene.json> --frames A-B[:S] [--repeat N] [--width W]\n"
              "                     [--height H] [--threads T] [--warmup N] [--set key=value]...\n"
              "                     [--oit NAME] [--serial-upload] [--scrub-back N]\n"
              "                     [--json out.json]\n"
              "  --repeat N        play the range N times (a longer run over the same files)\n"
              "  --threads T       prefetch workers (default 2); TBB uses every core inside each\n"
              "  --serial-upload   upload each frame's volumes right before its render, not\n"
              "                    during the previous frame's render\n"
              "  --scrub-back N    then show the N frames before the last one again, last first");
}

nlohmann::json stats(std::vector<double> v) {
    if (v.empty()) return nullptr;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    const double median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    const double mean = std::accumulate(v.begin(), v.end(), 0.0) / double(n);
    return {{"median", median}, {"mean", mean}, {"min", v.front()}, {"max", v.back()}};
}

struct Args {
    std::string scene, frames, json, oit;
    std::vector<std::string> overrides;
    int repeat = 1, width = 1920, height = 1080, threads = 2, warmup = 2, scrubBack = 0;
    bool serialUpload = false;
};

using Samples = std::map<std::string, std::vector<double>>;

// One played frame's times into `t`.
void record(const veil::sequence::PlayedFrame& f, double frameMs, Samples& t) {
    t["wait_ms"].push_back(f.waitMs);
    t["read_ms"].push_back(f.readMs);
    t["convert_ms"].push_back(f.convertMs);
    t["setup_ms"].push_back(f.setupMs);
    t["upload_ms"].push_back(f.uploadMs);
    t["uploaded_mb"].push_back(double(f.uploadedBytes) / 1048576.0);
    t["render_ms"].push_back(f.renderMs);
    t["ahead_ms"].push_back(f.aheadMs);
    t["frame_ms"].push_back(frameMs);
    double gpu = 0.0;
    for (const auto& pass : f.renderer->passTimes())
        gpu += pass.milliseconds;
    t["gpu_passes_ms"].push_back(gpu);
}

int run(const Args& a) {
    using namespace veil;
    gpu::HeadlessContext context;
    const scene::AnimatedScene scene = scene::loadAnimatedScene(a.scene, a.overrides);
    const std::vector<int> range = scene::parseFrameRange(a.frames).frames();
    std::vector<int> frames;
    for (int r = 0; r < std::max(a.repeat, 1); ++r)
        frames.insert(frames.end(), range.begin(), range.end());
    const frame::RendererOptions options(a.width, a.height, {}, a.oit);
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);

    // Warm-up: the first frames compile programs and ramp the clocks.
    for (int i = 0; i < a.warmup && i < int(range.size()); ++i) {
        const scene::Scene s = scene::sceneAtFrame(scene, range[i]);
        frame::Renderer renderer(s, context.info(), options);
        renderer.render();
        glFinish();
    }

    // The frames shown again when scrubbing back: those before the last, last first.
    std::vector<int> scrub;
    for (int i = int(frames.size()) - 2; i >= 0 && int(scrub.size()) < a.scrubBack; --i)
        scrub.push_back(frames[std::size_t(i)]);
    std::vector<int> played = frames;
    played.insert(played.end(), scrub.begin(), scrub.end());

    Samples t, back;
    std::vector<double> activeVoxels;
    auto start = Clock::now();
    double wallS = 0.0, scrubWallS = 0.0;
    int built = 0, reused = 0;
    std::size_t scrubUploads = 0, scrubBytes = 0, heldFrames = 0, heldBytes = 0;
    {
        sequence::RangePlayer player(scene, played, context.info(), options,
                                     std::size_t(scene.timeline.time.prefetchBudgetMiB) << 20,
                                     a.threads, max3D, !a.serialUpload);
        for (std::size_t i = 0; i < played.size(); ++i) {
            if (i == frames.size()) {
                wallS = std::chrono::duration<double>(Clock::now() - start).count();
                start = Clock::now();
            }
            const auto mark = Clock::now();
            const sequence::PlayedFrame f = player.step();
            const bool scrubbing = i >= frames.size();
            record(f, msSince(mark), scrubbing ? back : t);
            if (scrubbing) scrubUploads += f.uploads;
            if (scrubbing) scrubBytes += f.uploadedBytes;
            if (i + 1 == played.size() && f.renderer->fog()) // the frames held on the GPU
                for (const volume::GpuVolumeStats& v : f.renderer->fog()->stats()) {
                    heldFrames += v.heldFrames;
                    heldBytes += v.heldBytes;
                }
            if (!scrubbing) activeVoxels.push_back(double(f.activeVoxels));
        }
        const double s = std::chrono::duration<double>(Clock::now() - start).count();
        (scrub.empty() ? wallS : scrubWallS) = s;
        built = player.renderers().built();
        reused = player.renderers().reused();
    }

    // The distinct frames alone: upload, and the CPU conversion per million active voxels.
    std::vector<double> uploadMs, convertPerM, convertPerM1, uploadGBs, replaceMs, replaceGBs;
    std::unique_ptr<volume::GpuVolume> kept; // a range's volume: replace() into its textures
    std::set<std::string> seen;
    for (int f : range) {
        const scene::Scene s = scene::sceneAtFrame(scene, f);
        for (const scene::VolumeRef& v : s.volumes) {
            if (v.path.empty() || !seen.insert(v.path.string() + "|" + v.grid).second) continue;
            const openvdb::FloatGrid::Ptr grid = volume::loadVolume(v);
            volume::GpuVolumeOptions o;
            o.budgetBytes = std::size_t(s.render.volumeBudgetMiB) << 20;
            const double m = double(grid->activeVoxelCount()) / 1e6;
            auto mark = Clock::now();
            const volume::GridConversion c = volume::convertGrid(*grid, o, max3D);
            convertPerM.push_back(msSince(mark) / m);
            mark = Clock::now();
            (void)volume::convertGrid(*grid, o, max3D, 1);
            convertPerM1.push_back(msSince(mark) / m);
            glFinish();
            mark = Clock::now();
            {
                const volume::GpuVolume uploaded(c, glm::mat4(1.0f));
                glFinish();
                uploadMs.push_back(msSince(mark));
            }
            uploadGBs.push_back(double(c.bytes()) / (uploadMs.back() * 1e6));
            mark = Clock::now();
            if (kept) {
                kept->replace(c, glm::mat4(1.0f));
                glFinish();
                replaceMs.push_back(msSince(mark));
                replaceGBs.push_back(double(c.bytes()) / (replaceMs.back() * 1e6));
            } else {
                kept = std::make_unique<volume::GpuVolume>(c, glm::mat4(1.0f));
            }
        }
    }

    const auto& info = context.info();
    nlohmann::json out;
    out["mode"] = "frame range as `veil render --frames`, no image writes";
    out["scene"] = a.scene;
    out["width"] = a.width;
    out["height"] = a.height;
    out["frames"] = frames.size();
    out["range"] = a.frames;
    out["repeat"] = a.repeat;
    out["prefetch_threads"] = a.threads;
    out["tbb_threads"] = tbb::info::default_concurrency();
    out["renderer"] = info.renderer;
    out["gl_version"] = info.version;
    out["timer"] = info.softwareRenderer ? "glFinish + CPU clock" : "GL_TIME_ELAPSED";
    out["upload"] = a.serialUpload ? "serial: before each frame's render"
                                   : "overlapped: during the previous frame's render";
    out["renderers_built"] = built;
    out["gpu_frames"] = {{"budget_mib", scene.scene.render.sequenceGpuCacheMiB},
                         {"held_frames_at_end", heldFrames},
                         {"held_mb_at_end", double(heldBytes) / 1048576.0}};
    out["frames_reusing_the_renderer"] = reused;
    out["wall_s"] = wallS;
    out["end_to_end_fps"] = double(frames.size()) / wallS;
    out["active_voxels"] = stats(activeVoxels);
    for (const auto& [k, v] : t)
        out["per_frame"][k] = stats(v);
    // Shares of the render thread's frame.
    const double frameMs = out["per_frame"]["frame_ms"]["mean"];
    for (const char* k : {"wait_ms", "setup_ms", "upload_ms", "render_ms", "ahead_ms"})
        out["render_thread_share"][std::string(k).substr(0, std::strlen(k) - 3)] =
            out["per_frame"][k]["mean"].get<double>() / frameMs;
    if (!scrub.empty()) {
        out["scrub_back"]["frames"] = scrub;
        out["scrub_back"]["volume_uploads"] = scrubUploads; // 0: every frame held on the GPU
        out["scrub_back"]["uploaded_mb"] = double(scrubBytes) / 1048576.0;
        out["scrub_back"]["wall_s"] = scrubWallS;
        out["scrub_back"]["fps"] = double(scrub.size()) / scrubWallS;
        for (const auto& [k, v] : back)
            out["scrub_back"]["per_frame"][k] = stats(v);
    }
    out["distinct_frames"] = {
        {"upload_ms", stats(uploadMs)},
        {"upload_gb_per_s", stats(uploadGBs)},
        {"replace_upload_ms", stats(replaceMs)},
        {"replace_upload_gb_per_s", stats(replaceGBs)},
        {"convert_ms_per_million_active_voxels", stats(convertPerM)},
        {"convert_ms_per_million_active_voxels_1_thread", stats(convertPerM1)}};
    // bench/run.py's pass list: the stages' means as "passes" so a group's metric can pick one.
    nlohmann::json passes = nlohmann::json::array();
    for (const char* k :
         {"wait_ms", "read_ms", "convert_ms", "setup_ms", "upload_ms", "render_ms", "ahead_ms"})
        passes.push_back({{"name", std::string(k).substr(0, std::strlen(k) - 3)},
                          {"median_ms", out["per_frame"][k]["median"]},
                          {"min_ms", out["per_frame"][k]["min"]},
                          {"max_ms", out["per_frame"][k]["max"]}});
    passes.push_back(
        {{"name", "frame"}, {"median_ms", 1000.0 / out["end_to_end_fps"].get<double>()}});
    if (!scrub.empty()) {
        const auto& b = out["scrub_back"]["per_frame"];
        passes.push_back({{"name", "scrub_back_frame"},
                          {"median_ms", b["frame_ms"]["median"]},
                          {"min_ms", b["frame_ms"]["min"]},
                          {"max_ms", b["frame_ms"]["max"]}});
        passes.push_back({{"name", "scrub_back_upload"},
                          {"median_ms", b["upload_ms"]["median"]},
                          {"min_ms", b["upload_ms"]["min"]},
                          {"max_ms", b["upload_ms"]["max"]}});
    }
    out["passes"] = passes;
    out["total_median_ms"] = 1000.0 / out["end_to_end_fps"].get<double>(); // run.py's "frame"
    const std::string text = out.dump(2);
    if (!a.json.empty())
        writeFileAtomically(
            a.json, [&](const std::filesystem::path& tmp) { std::ofstream(tmp) << text << "\n"; });
    std::cout << text << "\n";
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    Args a;
    for (int i = 1; i < argc; ++i) {
        const std::string s = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) {
                usage();
                std::exit(2);
            }
            return argv[++i];
        };
        try {
            if (s == "--frames")
                a.frames = next();
            else if (s == "--repeat")
                a.repeat = std::stoi(next());
            else if (s == "--width")
                a.width = std::stoi(next());
            else if (s == "--height")
                a.height = std::stoi(next());
            else if (s == "--threads")
                a.threads = std::stoi(next());
            else if (s == "--warmup")
                a.warmup = std::stoi(next());
            else if (s == "--scrub-back")
                a.scrubBack = std::stoi(next());
            else if (s == "--serial-upload")
                a.serialUpload = true;
            else if (s == "--set")
                a.overrides.push_back(next());
            else if (s == "--json")
                a.json = next();
            else if (s == "-h" || s == "--help") {
                usage();
                return 0;
            } else if (a.scene.empty() && s[0] != '-')
                a.scene = s;
            else {
                usage();
                return 2;
            }
        } catch (const std::exception&) {
            std::fprintf(stderr, "veil-seqbench: bad value for %s\n", s.c_str());
            return 2;
        }
    }
    if (a.scene.empty() || a.frames.empty() || a.width < 1 || a.height < 1 || a.scrubBack < 0) {
        usage();
        return 2;
    }
    try {
        return run(a);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "veil-seqbench: %s\n", e.what());
        return 1;
    }
}
