// veil-bench: renders a scene N frames after warm-up and writes per-pass median/min/max GPU
// times as JSON. Links the core only (no OpenImageIO, no VTK) so it travels to the GPU
// machine (bench/README.md: bench/gpu-bundle.sh). Times are GL_TIME_ELAPSED queries where the
// driver has them. bench/run.py runs it over the benchmark sets of bench/sets/.
#include "base/atomic_file.h"
#include "base/error.h"
#include "bench_stats.h"
#include "fog/fog_pass.h"
#include "frame/renderer.h"
#include "gpu/context.h"
#include "grid/density_grid.h"
#include "integrators/cpu_reference.h"
#include "integrators/path_tracer.h"
#include "scattered_light_bench.h"
#include "scene/scene.h"
#include "viewer/session/view_session.h"
#include "viewer_play_bench.h"

#include <chrono>
#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

namespace {

void usage() {
    std::puts(
        "usage: veil-bench <scene.json> [--width W] [--height H] [--frames N] [--warmup N]\n"
        "                  [--oit NAME] [--set key=value]... [--json out.json]\n"
        "                  [--viewer]  (the frames of `veil view`, windowless)\n"
        "                  [--viewer-play [--scrub-back M]]  the viewer's timeline played\n"
        "                                   windowless: --frames frames after --warmup,\n"
        "                                   then M frames stepped backwards\n"
        "                  [--cpu-fog W H]  also time the CPU fog reference (double\n"
        "                                   precision, all cores) on the same view at W x H\n"
        "                  [--error-vs NAME] also render the last frame with OIT technique\n"
        "                                   NAME (e.g. reference) and report the HDR\n"
        "                                   difference (rgb rmse, max) as error_vs\n"
        "                  [--relight]      recompute the fog's light volumes every frame\n"
        "                  [--light-drag DEG] turn the first light DEG degrees every frame\n"
        "                                   with the progressive scattered-light bake\n"
        "                  [--converge]     with --light-drag: the cache's error after the drag\n"
        "                  [--ppm out.ppm]  write the last frame as displayed (8-bit binary PPM)\n"
        "                  [--pfm out.pfm]  write the last frame's linear radiance (float PFM)\n"
        "       veil-bench <scene.json> --pathtraced SPP SEED out.pfm [--width W] [--height H]\n"
        "                  [--set key=value]...  the CPU path tracer only (no GL): linear\n"
        "                                   radiance and out-stderr.pfm, all cores, with its\n"
        "                                   time and samples per second in the JSON\n"
        "       veil-bench <scene.json> --surface-pathtraced SPP SEED out.pfm [--width W]\n"
        "                  [--height H] [--set key=value]...  the path tracer's light on the\n"
        "                                   first surface each pixel sees: base colour / pi x\n"
        "                                   its irradiance (SPP paths), and out-stderr.pfm");
}

// Prints the result and writes it to `jsonPath` (atomically) when given; the exit status.
int printResult(const nlohmann::json& out, const std::string& jsonPath) {
    const std::string text = out.dump(2);
    if (!jsonPath.empty())
        veil::writeFileAtomically(jsonPath, [&](const std::filesystem::path& tmp) {
            std::ofstream f(tmp);
            f << text << "\n";
        });
    std::cout << text << "\n";
    return 0;
}

using veil::bench::median;

double wallMs(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// --viewer: the frames of `veil view` without its window (viewer/session/view_session.h): each
// frame is ViewSession::renderFrame() (the renderer's passes and the copy into the shown image),
// timed by GL timer queries per pass and by the CPU clock around the frame with glFinish;
// the same CPU clock around Renderer::render() alone in the same run gives the viewer's
// overhead as a ratio. Then the cost of the panel's edits: a volume's density (live), the
// OIT technique (the technique alone) and the fog resolution (a new renderer).
int viewerBench(const std::string& scenePath, const std::vector<std::string>& overrides, int width,
                int height, int frames, int warmup, const std::string& jsonPath) {
    veil::gpu::HeadlessContext context;
    veil::session::ViewSession session(context.info(), scenePath, overrides, "", width, height);
    for (int i = 0; i < warmup; ++i) {
        session.renderFrame();
        glFinish();
    }
    std::map<std::string, std::vector<double>> samples;
    std::vector<std::string> order;
    std::vector<double> gpuTotals, viewerWall, rendererWall;
    for (int i = 0; i < frames; ++i) {
        auto t0 = std::chrono::steady_clock::now();
        VEIL_CHECK(session.renderFrame(), "viewer frame failed: {}", session.lastError());
        glFinish();
        viewerWall.push_back(wallMs(t0));
        double total = 0.0;
        for (const auto& p : session.renderer().passTimes()) {
            if (!samples.count(p.name)) order.push_back(p.name);
            samples[p.name].push_back(p.milliseconds);
            total += p.milliseconds;
        }
        gpuTotals.push_back(total);
        t0 = std::chrono::steady_clock::now();
        session.renderer().render();
        glFinish();
        rendererWall.push_back(wallMs(t0));
    }
    nlohmann::json out;
    out["mode"] = "viewer frame path (ViewSession::renderFrame, no window)";
    out["scene"] = scenePath;
    out["width"] = width;
    out["height"] = height;
    out["frames"] = frames;
    out["warmup"] = warmup;
    out["oit"] = session.renderer().oitName();
    out["shadows"] = session.renderer().shadowTechnique().name();
    out["overrides"] = session.overrides();
    out["renderer"] = context.info().renderer;
    nlohmann::json passes = nlohmann::json::array();
    for (const auto& name : order)
        passes.push_back({{"name", name}, {"median_ms", median(samples[name])}});
    out["passes"] = passes;
    out["gpu_total_median_ms"] = median(gpuTotals);
    out["viewer_frame_wall_median_ms"] = median(viewerWall);
    out["renderer_frame_wall_median_ms"] = median(rendererWall);
    out["viewer_over_renderer"] = median(viewerWall) / median(rendererWall);
    // Edits, each followed by its frame (median of 5 alternations).
    auto editMs = [&](const std::string& a, const std::string& b) {
        std::vector<double> v;
        for (int i = 0; i < 5; ++i) {
            auto t0 = std::chrono::steady_clock::now();
            VEIL_CHECK(session.set(i % 2 ? b : a), "{}", session.lastError());
            glFinish();
            v.push_back(wallMs(t0));
            session.renderFrame();
        }
        return median(v);
    };
    nlohmann::json edits;
    if (!session.scene().volumes.empty()) {
        const float d = session.scene().volumes[0].densityScale;
        edits["volume_density_live_ms"] =
            editMs(fmt::format("volumes.0.density_scale={}", d * 1.5f),
                   fmt::format("volumes.0.density_scale={}", d));
        const int r = session.scene().render.fogResolution;
        edits["fog_resolution_new_renderer_ms"] =
            editMs(fmt::format("render.fog_resolution={}", r == 1 ? 2 : 1),
                   fmt::format("render.fog_resolution={}", r));
    }
    const std::string oit = session.renderer().oitName();
    edits["oit_technique_switch_ms"] =
        editMs("render.oit={\"type\":\"wboit\"}", "render.oit={\"type\":\"" + oit + "\"}");
    edits["note"] = "wall clock of ViewSession::set() + glFinish (scene re-parse included)";
    out["edits"] = edits;
    return printResult(out, jsonPath);
}

// The displayed (tone-mapped, sRGB-encoded) frame as an 8-bit binary PPM: no image library in
// the benchmark programs, so that they bundle small (bench/gpu-bundle.sh).
void writePpm(const std::string& path, const veil::ImageF& image) {
    veil::writeFileAtomically(path, [&](const std::filesystem::path& tmp) {
        std::ofstream f(tmp, std::ios::binary);
        f << "P6\n" << image.width << " " << image.height << "\n255\n";
        std::vector<unsigned char> row(std::size_t(image.width) * 3);
        for (int y = 0; y < image.height; ++y) {
            for (int x = 0; x < image.width; ++x)
                for (int c = 0; c < 3; ++c) {
                    const float v = image.at(x, y, c);
                    row[std::size_t(x) * 3 + c] =
                        static_cast<unsigned char>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
                }
            f.write(reinterpret_cast<const char*>(row.data()), std::streamsize(row.size()));
        }
        VEIL_CHECK(f.good(), "cannot write {}", path);
    });
}

// Little-endian RGB PFM (rows bottom to top), the float format every image tool reads.
void writePfm(const std::string& path, const veil::ImageF& image) {
    veil::writeFileAtomically(path, [&](const std::filesystem::path& tmp) {
        std::ofstream f(tmp, std::ios::binary);
        f << "PF\n" << image.width << " " << image.height << "\n-1.0\n";
        std::vector<float> row(std::size_t(image.width) * 3);
        for (int y = image.height - 1; y >= 0; --y) {
            for (int x = 0; x < image.width; ++x)
                for (int c = 0; c < 3; ++c)
                    row[std::size_t(x) * 3 + c] = image.at(x, y, c);
            f.write(reinterpret_cast<const char*>(row.data()),
                    std::streamsize(row.size() * sizeof(float)));
        }
        VEIL_CHECK(f.good(), "cannot write {}", path);
    });
}

// --pathtraced: the CPU path tracer (src/integrators/path_tracer.h) on the scene's camera, all
// cores; for references made on a machine with more cores than a developer's.
int pathTracedBench(const std::string& scenePath, const std::vector<std::string>& overrides,
                    int width, int height, int spp, std::uint32_t seed, const std::string& pfm,
                    const std::string& jsonPath) {
    const veil::scene::Scene scene = veil::scene::loadScene(scenePath, overrides);
    std::vector<openvdb::FloatGrid::ConstPtr> grids;
    for (const auto& v : scene.volumes)
        grids.push_back(v.procedural == "homogeneous" ? nullptr : veil::volume::loadVolume(v));
    veil::volume::PathTracerSettings settings;
    settings.spp = spp;
    settings.seed = seed;
    const veil::volume::VolumePathTracer tracer(scene, grids, settings);
    const auto t0 = std::chrono::steady_clock::now();
    const veil::volume::PathTracedImage image = tracer.render(scene.camera(), width, height);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    writePfm(pfm, image.radiance);
    const std::string stem = pfm.substr(0, pfm.size() - (pfm.ends_with(".pfm") ? 4 : 0));
    writePfm(stem + "-stderr.pfm", image.standardError);
    nlohmann::json out{{"scene", scenePath},
                       {"width", width},
                       {"height", height},
                       {"spp", image.samples},
                       {"seed", seed},
                       {"seconds", s},
                       {"threads", std::thread::hardware_concurrency()},
                       {"samples_per_second", double(width) * height * image.samples / s},
                       {"majorant", tracer.majorant()},
                       {"pfm", pfm}};
    return printResult(out, jsonPath);
}

// The nearest hit of a ray with the scene's triangles (world space): distance and the
// triangle's unit normal facing the ray's origin, or false. Brute force: the scenes this
// serves have a floor and a few objects.
struct SurfaceHit {
    double t = 1e300;
    glm::dvec3 normal{0.0};
    std::uint32_t material = 0;
};
bool intersectScene(const veil::scene::Scene& scene, const glm::dvec3& o, const glm::dvec3& d,
                    double tMax, SurfaceHit& hit) {
    bool found = false;
    for (const auto& object : scene.objects) {
        const auto& mesh = scene.meshes.at(object.mesh);
        const glm::dmat4 m(object.transform);
        auto world = [&](std::uint32_t i) {
            return glm::dvec3(m * glm::dvec4(glm::dvec3(mesh.positions[i]), 1.0));
        };
        for (std::size_t k = 0; k + 2 < mesh.indices.size(); k += 3) {
            // Moller-Trumbore.
            const glm::dvec3 a = world(mesh.indices[k]), b = world(mesh.indices[k + 1]),
                             c = world(mesh.indices[k + 2]);
            const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
            const double det = glm::dot(e1, p);
            if (std::abs(det) < 1e-14) continue;
            const glm::dvec3 s = o - a;
            const double u = glm::dot(s, p) / det;
            if (u < 0.0 || u > 1.0) continue;
            const glm::dvec3 q = glm::cross(s, e1);
            const double v = glm::dot(d, q) / det, t = glm::dot(e2, q) / det;
            if (v < 0.0 || u + v > 1.0 || t <= 0.0 || t >= std::min(tMax, hit.t)) continue;
            glm::dvec3 n = glm::normalize(glm::cross(e1, e2));
            hit = {t, glm::dot(n, d) > 0.0 ? -n : n, object.material};
            found = true;
        }
    }
    return found;
}

// --surface-pathtraced: the reference for surfaces lit by the scattered-light cache. Per pixel,
// the camera ray's first surface point (no volume in front of it is accounted for: the view
// must see the surface through empty space), its Lambertian radiance base colour / pi x E with
// E the path tracer's irradiance there (VolumePathTracer::surfaceIrradiance, cosine-weighted
// paths with the tracer's own transport); pixels that see no surface are 0. All cores.
int surfaceBench(const std::string& scenePath, const std::vector<std::string>& overrides, int width,
                 int height, int spp, std::uint32_t seed, const std::string& pfm,
                 const std::string& jsonPath) {
    const veil::scene::Scene scene = veil::scene::loadScene(scenePath, overrides);
    VEIL_CHECK(!scene.objects.empty(), "{}: --surface-pathtraced needs objects in the scene",
               scenePath);
    VEIL_CHECK(spp >= 2, "--surface-pathtraced: SPP must be at least 2 ({})", spp);
    std::vector<openvdb::FloatGrid::ConstPtr> grids;
    for (const auto& v : scene.volumes)
        grids.push_back(v.procedural == "homogeneous" ? nullptr : veil::volume::loadVolume(v));
    veil::volume::PathTracerSettings settings;
    settings.seed = seed;
    const veil::volume::VolumePathTracer tracer(scene, grids, settings);
    veil::ImageF radiance(width, height, 3), error(width, height, 3);
    const auto t0 = std::chrono::steady_clock::now();
    std::atomic<int> nextRow{0}, surfacePixels{0};
    auto work = [&] {
        for (int y; (y = nextRow++) < height;)
            for (int x = 0; x < width; ++x) {
                const auto ray =
                    veil::volume::cameraRay(scene.camera(), width, height, x + 0.5, y + 0.5);
                SurfaceHit hit;
                if (!intersectScene(scene, ray.origin, ray.direction, ray.length, hit)) continue;
                const glm::dvec3 p = ray.origin + hit.t * ray.direction + 1e-6 * hit.normal;
                glm::dvec3 se;
                const glm::dvec3 e = tracer.surfaceIrradiance(
                    p, hit.normal, spp, std::uint64_t(y) * std::uint64_t(width) + x, &se);
                const glm::dvec3 albedo(scene.materials.at(hit.material).baseColor);
                for (int c = 0; c < 3; ++c) {
                    radiance.at(x, y, c) = float(albedo[c] / std::numbers::pi * e[c]);
                    error.at(x, y, c) = float(albedo[c] / std::numbers::pi * se[c]);
                }
                ++surfacePixels;
            }
    };
    std::vector<std::thread> threads;
    for (unsigned i = 0; i < std::max(1u, std::thread::hardware_concurrency()); ++i)
        threads.emplace_back(work);
    for (auto& t : threads)
        t.join();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    writePfm(pfm, radiance);
    const std::string stem = pfm.substr(0, pfm.size() - (pfm.ends_with(".pfm") ? 4 : 0));
    writePfm(stem + "-stderr.pfm", error);
    nlohmann::json out{{"scene", scenePath},
                       {"width", width},
                       {"height", height},
                       {"spp", spp},
                       {"seed", seed},
                       {"seconds", s},
                       {"surface_pixels", int(surfacePixels)},
                       {"threads", std::thread::hardware_concurrency()},
                       {"pfm", pfm}};
    return printResult(out, jsonPath);
}

} // namespace

int main(int argc, char** argv) try {
    std::string scenePath, jsonPath, oit, errorVs, ppmPath, pfmPath, framePfmPath;
    int width = 1920, height = 1080, frames = 100, warmup = 20, cpuFogW = 0, cpuFogH = 0;
    int ptSpp = 0;
    bool surface = false;
    std::uint32_t ptSeed = 1;
    bool relight = false, converge = false;
    double dragDegrees = 0.0;
    bool viewer = false;
    bool viewerPlay = false;
    int scrubBack = 0;
    std::vector<std::string> overrides;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            VEIL_CHECK(i + 1 < argc, "{} needs a value", a);
            return argv[++i];
        };
        if (a == "--width")
            width = std::stoi(next());
        else if (a == "--height")
            height = std::stoi(next());
        else if (a == "--frames")
            frames = std::stoi(next());
        else if (a == "--warmup")
            warmup = std::stoi(next());
        else if (a == "--oit")
            oit = next();
        else if (a == "--set")
            overrides.push_back(next());
        else if (a == "--relight")
            relight = true;
        else if (a == "--light-drag")
            dragDegrees = std::stod(next());
        else if (a == "--converge")
            converge = true;
        else if (a == "--json")
            jsonPath = next();
        else if (a == "--viewer")
            viewer = true;
        else if (a == "--viewer-play")
            viewerPlay = true;
        else if (a == "--scrub-back")
            scrubBack = std::stoi(next());
        else if (a == "--error-vs")
            errorVs = next();
        else if (a == "--ppm")
            ppmPath = next();
        else if (a == "--pfm")
            framePfmPath = next();
        else if (a == "--pathtraced" || a == "--surface-pathtraced") {
            surface = a == "--surface-pathtraced";
            ptSpp = std::stoi(next());
            ptSeed = std::uint32_t(std::stoul(next()));
            pfmPath = next();
        } else if (a == "--cpu-fog") {
            cpuFogW = std::stoi(next());
            cpuFogH = std::stoi(next());
        } else if (a == "-h" || a == "--help") {
            usage();
            return 0;
        } else if (!a.empty() && a[0] == '-')
            throw veil::Error("unknown option " + a);
        else
            scenePath = a;
    }
    if (scenePath.empty()) {
        usage();
        return 2;
    }
    VEIL_CHECK(frames > 0 && warmup >= 0, "--frames must be > 0 and --warmup >= 0");
    if (ptSpp > 0 && surface)
        return surfaceBench(scenePath, overrides, width, height, ptSpp, ptSeed, pfmPath, jsonPath);
    if (ptSpp > 0)
        return pathTracedBench(scenePath, overrides, width, height, ptSpp, ptSeed, pfmPath,
                               jsonPath);
    VEIL_CHECK(!converge || dragDegrees != 0.0, "--converge needs --light-drag DEG");
    if (dragDegrees != 0.0)
        return veil::bench::lightDragBench({scenePath, oit, jsonPath, overrides, width, height,
                                            frames, warmup, dragDegrees, converge});
    if (viewerPlay)
        return veil::bench::viewerPlayBench(
            {scenePath, jsonPath, overrides, width, height, frames, warmup, scrubBack});
    if (viewer) return viewerBench(scenePath, overrides, width, height, frames, warmup, jsonPath);
    const veil::scene::Scene scene = veil::scene::loadScene(scenePath, overrides);
    veil::gpu::HeadlessContext context;
    veil::frame::Renderer renderer(scene, context.info(), {width, height, {}, oit});
    for (int i = 0; i < warmup; ++i) {
        if (relight) renderer.invalidateFogLightVolumes();
        renderer.render();
    }
    std::map<std::string, std::vector<double>> samples, cpuSamples;
    std::vector<std::string> order;
    std::vector<double> totals;
    for (int i = 0; i < frames; ++i) {
        if (relight) renderer.invalidateFogLightVolumes();
        renderer.render();
        double total = 0.0;
        for (const auto& p : renderer.passTimes()) {
            if (!samples.count(p.name)) order.push_back(p.name);
            samples[p.name].push_back(p.milliseconds);
            if (p.cpuMilliseconds >= 0.0) cpuSamples[p.name].push_back(p.cpuMilliseconds);
            total += p.milliseconds;
        }
        totals.push_back(total);
    }
    nlohmann::json out;
    out["scene"] = scenePath;
    out["width"] = width;
    out["height"] = height;
    out["frames"] = frames;
    out["warmup"] = warmup;
    out["relight"] = relight;
    out["oit"] = renderer.oitName();
    out["shadows"] = renderer.shadowTechnique().name();
    out["shadow_properties"] = renderer.shadowTechnique().properties().values();
    out["shadow_stats"] = renderer.shadowTechnique().stats(); // of the last frame
    out["renderer"] = context.info().renderer;
    out["gl_version"] = context.info().version;
    out["timer"] = renderer.timerMode() == veil::gpu::GpuTimer::Mode::Query ? "GL_TIME_ELAPSED"
                                                                            : "glFinish+cpu";
    std::size_t triangles = 0;
    for (const auto& o : scene.objects)
        triangles += scene.meshes.at(o.mesh).triangleCount();
    out["triangles"] = triangles;
    nlohmann::json passes = nlohmann::json::array();
    for (const auto& name : order) {
        const auto& v = samples[name];
        passes.push_back({{"name", name},
                          {"median_ms", median(v)},
                          {"min_ms", *std::min_element(v.begin(), v.end())},
                          {"max_ms", *std::max_element(v.begin(), v.end())}});
        // llvmpipe: the process's CPU time over the pass (all driver threads).
        if (!cpuSamples[name].empty()) passes.back()["cpu_median_ms"] = median(cpuSamples[name]);
    }
    // The scattered-light cache's bake (before the first frame, outside the passes): one sample.
    if (const veil::volume::FogPass* fog = renderer.fog();
        fog && fog->scatteredLightBakeMs() >= 0) {
        const double ms = fog->scatteredLightBakeMs();
        passes.push_back(
            {{"name", "scattered_light_bake"}, {"median_ms", ms}, {"min_ms", ms}, {"max_ms", ms}});
    }
    out["passes"] = passes;
    out["total_median_ms"] = median(totals);
    out["total_min_ms"] = *std::min_element(totals.begin(), totals.end());
    out["total_max_ms"] = *std::max_element(totals.begin(), totals.end());
    out["oit_stats"] = renderer.technique().stats();
    if (!ppmPath.empty()) {
        writePpm(ppmPath, renderer.readLdr());
        out["ppm"] = ppmPath;
    }
    if (!framePfmPath.empty()) {
        writePfm(framePfmPath, renderer.readHdr()); // RGB of the RGBA radiance
        out["pfm"] = framePfmPath;
    }
    if (cpuFogW > 0 && cpuFogH > 0) {
        // The CPU reference of the fog on the same camera (src/integrators/cpu_reference.h).
        std::vector<openvdb::FloatGrid::ConstPtr> grids;
        for (const auto& v : scene.volumes)
            if (v.procedural != "homogeneous") grids.push_back(veil::volume::loadVolume(v));
        const veil::volume::CpuFogReference ref(scene, grids);
        const auto t0 = std::chrono::steady_clock::now();
        ref.render(renderer.camera(), cpuFogW, cpuFogH, scene.render.fogSteps);
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        out["cpu_fog"] = {{"width", cpuFogW},
                          {"height", cpuFogH},
                          {"steps", scene.render.fogSteps},
                          {"ms", ms},
                          {"ns_per_pixel", ms * 1e6 / (double(cpuFogW) * cpuFogH)}};
        for (const auto& p : out["passes"])
            if (p["name"] == "fog")
                out["cpu_fog"]["gpu_fog_ns_per_pixel"] =
                    p["median_ms"].get<double>() * 1e6 / (double(width) * height);
    }
    if (!errorVs.empty()) {
        // The image error of this technique against another on the same frame (GPU checks of
        // paths the CPU driver cannot run, e.g. fragment shader interlock).
        const veil::gpu::ImageF mine = renderer.readHdr();
        veil::frame::Renderer other(scene, context.info(), {width, height, {}, errorVs});
        other.render();
        const veil::gpu::ImageF theirs = other.readHdr();
        VEIL_CHECK(mine.pixels.size() == theirs.pixels.size(), "--error-vs: image sizes differ");
        double sum = 0.0, worst = 0.0;
        std::size_t count = 0, nonFinite = 0;
        for (std::size_t i = 0; i < mine.pixels.size(); ++i) {
            if (i % 4 == 3) continue; // rgb only
            const double d = double(mine.pixels[i]) - double(theirs.pixels[i]);
            if (!std::isfinite(d)) {
                ++nonFinite;
                continue;
            }
            sum += d * d;
            worst = std::max(worst, std::abs(d));
            ++count;
        }
        out["error_vs"] = {{"technique", other.oitName()},
                           {"rmse", std::sqrt(sum / double(std::max<std::size_t>(count, 1)))},
                           {"max", worst},
                           {"non_finite", nonFinite}};
    }
    return printResult(out, jsonPath);
} catch (const std::exception& e) {
    std::fprintf(stderr, "veil-bench: error: %s\n", e.what());
    return 1;
}
