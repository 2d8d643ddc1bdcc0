// `veil voxelize scene.json|mesh.{obj,ply,glb,gltf} --res 256 --slices 256 [--solid] [--method M]
// [--local]
//  [--perspective [--camera NAME]] -o grid.vdb [--vti grid.vti] [--smooth W]`:
// slice-map voxelization on the GPU (src/voxelize), written as OpenVDB grids ("density",
// "mask") and optionally as a VTK image for ParaView. A mesh file is voxelized without a
// scene: cubic voxels of (largest extent x 1.06) / res, the grid fitted to the mesh bounds on
// every axis (so a flat mesh gets few slices).
//
// --frame N / --frames A-B[:S]: a scene is voxelized at each frame (time.frame: its animated
// camera for --perspective, its meshes); a mesh input is then a file sequence (mesh.####.obj)
// and each frame's file is voxelized. Outputs take the frame number (-o grid.####.vdb, --vti
// grid.####.vti); every frame's input is checked before the first is voxelized; one GL context
// serves every frame; each file is written atomically.
#include "app/commands.h"
#include "app/shared_options.h"

#include "app/cli_checks.h"
#include "app/shared_options.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "gpu/context.h"
#include "io/vtk_export.h"
#include "scene/scene.h"
#include "scene/timeline.h"
#include "voxelize/pipeline.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

namespace veil::app {

namespace fs = std::filesystem;

namespace {

struct VoxelizeArgs {
    std::string scene, output, vti, method, camera;
    int res = 256, slices = 0, device = -1;
    bool solid = false, local = false, perspective = false, quiet = false;
    double smooth = 0.0, voxelSize = 0.0;
    double smoothLimit = 5e9;
    std::vector<std::string> overrides;
    FrameOptions frames;
};

// One frame's files: the input (a scene or a mesh file), the outputs, the scene's overrides.
struct VoxelizeFrame {
    std::string input, output, vti;
    std::vector<std::string> overrides;
};

// A one-line progress bar on stderr, redrawn in place.
class ProgressBar {
public:
    ProgressBar(std::string label, bool enabled) : label_(std::move(label)), enabled_(enabled) {}
    ~ProgressBar() {
        if (enabled_ && drawn_) std::fputc('\n', stderr);
    }
    void operator()(double fraction) {
        const int percent = static_cast<int>(fraction * 100.0 + 0.5);
        if (!enabled_ || percent == lastPercent_) return;
        lastPercent_ = percent;
        const int filled = static_cast<int>(fraction * 30.0 + 0.5);
        std::fprintf(stderr, "\r%-12s [%-30s] %3d%%", label_.c_str(),
                     std::string(std::size_t(std::clamp(filled, 0, 30)), '#').c_str(), percent);
        std::fflush(stderr);
        drawn_ = true;
    }

private:
    std::string label_;
    bool enabled_, drawn_ = false;
    int lastPercent_ = -1;
};

// The checks that need no GL, in order: outputs, mesh options, the scene (its files) and the
// outputs against the scene's own .vdb volumes (-o smoke.vdb would replace one).
scene::Scene loadFrameScene(const VoxelizeArgs& args, const VoxelizeFrame& frame) {
    using namespace veil::voxelize;
    checkOutputPath(frame.output, "output", {frame.input});
    if (!frame.vti.empty()) checkOutputPath(frame.vti, "--vti", {frame.input, frame.output});
    const bool mesh = isMeshFile(frame.input);
    if (mesh && (args.perspective || !args.overrides.empty()))
        usageError(
            fmt::format("'{}' is a mesh: --perspective and --set need a scene file", frame.input));
    scene::Scene scene =
        mesh ? sceneForMesh(frame.input) : scene::loadScene(frame.input, frame.overrides);
    std::vector<fs::path> volumeFiles;
    for (const scene::VolumeRef& v : scene.volumes)
        if (!v.path.empty()) volumeFiles.push_back(v.path);
    checkOutputPath(frame.output, "output", volumeFiles);
    return scene;
}

void voxelizeFrame(const VoxelizeArgs& args, const VoxelizeFrame& frame, const scene::Scene& scene,
                   voxelize::Method method, std::optional<gpu::HeadlessContext>& contextSlot) {
    using namespace veil::voxelize;
    const auto start = std::chrono::steady_clock::now();
    const bool mesh = isMeshFile(frame.input);
    Voxelization v =
        prepareVoxelization(scene, {args.res, args.slices, args.perspective, args.camera}, mesh);
    const SliceMap& grid = v.grid;
    if (!contextSlot) contextSlot.emplace(gpu::HeadlessOptions{args.device, false});
    gpu::HeadlessContext& context = *contextSlot;
    const bool big =
        v.triangles.count() > 200000 || double(args.res) * args.res * grid.slices > 6.4e7;
    {
        ProgressBar bar("voxelize", big && !args.quiet);
        fillGrid(v, context.info(), {method, args.solid, args.local}, [&bar](double f) { bar(f); });
    }
    VdbOptions vopt;
    vopt.smoothing = args.smooth;
    vopt.smoothingWorkLimit = args.smoothLimit;
    vopt.resampleVoxel = args.voxelSize;
    VdbGrids grids;
    {
        ProgressBar bar("to OpenVDB", big && !args.quiet);
        vopt.progress = [&bar](double f) { bar(f); };
        grids = toVdbNamed(grid, vopt, frame.input);
    }
    writeVdb(frame.output, grids);
    if (!frame.vti.empty()) {
        io::DenseGrid dense;
        dense.name = "density";
        for (int i = 0; i < 3; ++i) {
            dense.dims[i] = grids.dims[i];
            dense.origin[i] = grids.origin[i];
            dense.spacing[i] = grids.voxel[i];
        }
        dense.values.assign(std::size_t(grids.dims.x) * grids.dims.y * grids.dims.z, 0.0f);
        // Point index of a voxel in the grid's box; -1 outside (smoothing spills past the box;
        // the .vti keeps the grid's box).
        const auto point = [&grids](const openvdb::Coord& c) -> std::ptrdiff_t {
            if (c.x() < 0 || c.y() < 0 || c.z() < 0 || c.x() >= grids.dims.x ||
                c.y() >= grids.dims.y || c.z() >= grids.dims.z)
                return -1;
            return (std::ptrdiff_t(c.z()) * grids.dims.y + c.y()) * grids.dims.x + c.x();
        };
        for (auto it = grids.density->cbeginValueOn(); it; ++it)
            if (const std::ptrdiff_t i = point(it.getCoord()); i >= 0) dense.values[i] = *it;
        // The occupancy itself (the .vdb's "mask" grid) as a second array, 1 in a set voxel.
        std::vector<float> mask(dense.values.size(), 0.0f);
        for (auto it = grids.mask->cbeginValueOn(); it; ++it)
            if (const std::ptrdiff_t i = point(it.getCoord()); i >= 0) mask[i] = 1.0f;
        dense.moreScalars.emplace_back("mask", std::move(mask));
        dense.fieldData = {{"veil_source", frame.input},
                           {"veil_grids", "density, mask (as in " + frame.output + ")"},
                           {"veil_version", versionWithCommit()},
                           {"veil_command", commandLine()}};
        io::writeVti(frame.vti, dense);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << fmt::format(
        "voxelized {} triangles into {}x{}x{} {} cells: {} set ({} voxels in '{}')\n"
        "method: {}\ngrid: {}\ntime: voxelize {:.2f} ms ({}), total {:.2f} s\nwrote {}{}\n",
        v.triangles.count(), grid.width, grid.height, grid.slices, args.solid ? "solid" : "surface",
        grid.countSet(), grids.mask->activeVoxelCount(), frame.output, v.path, grids.note,
        v.milliseconds,
        context.info().softwareRenderer ? "glFinish + CPU clock" : "GL_TIME_ELAPSED", seconds,
        frame.output, frame.vti.empty() ? "" : " and " + frame.vti);
}

void runVoxelize(const VoxelizeArgs& args) {
    using namespace veil::voxelize;
    // Everything that can be checked before work is checked first, for every frame.
    const Method method =
        parseMethod(args.method.empty() ? (args.solid ? "raster" : "conservative") : args.method);
    if (lowerExtension(args.output) != ".vdb")
        usageError(fmt::format("output '{}' must end in .vdb", args.output));
    if (!args.vti.empty() && lowerExtension(args.vti) != ".vti")
        usageError(fmt::format("--vti '{}' must end in .vti", args.vti));
    if (!args.vti.empty()) io::requireVti(args.vti);
    const std::vector<int> frames = args.frames.list();
    std::vector<VoxelizeFrame> jobs;
    if (frames.empty()) {
        // A mesh name with a frame pattern (m.####.obj) and no such file is a sequence.
        const std::string input = isMeshFile(args.scene)
                                      ? inputForFrame(args.scene, std::nullopt, "input").string()
                                      : args.scene;
        jobs.push_back({input, args.output, args.vti, args.overrides});
    } else {
        // A scene file is taken at each frame; a mesh input is a file sequence.
        std::error_code ec;
        const bool sceneFile = fs::is_regular_file(args.scene, ec) && !isMeshFile(args.scene);
        if (!sceneFile) checkFrameInputs(args.scene, frames);
        if (sceneFile) { // every frame's volume files exist (or are held) before any work
            const scene::AnimatedScene animated =
                scene::loadAnimatedScene(args.scene, args.overrides);
            for (int f : frames)
                scene::volumeFrames(animated, f);
        }
        for (int f : frames) {
            VoxelizeFrame job;
            job.input = sceneFile ? args.scene : inputForFrame(args.scene, f, "input").string();
            job.output = outputForFrame(args.output, f, frames.size() == 1, "output").string();
            if (!args.vti.empty())
                job.vti = outputForFrame(args.vti, f, frames.size() == 1, "--vti").string();
            job.overrides = args.overrides;
            if (sceneFile) job.overrides.push_back(fmt::format("time.frame={}", f));
            jobs.push_back(std::move(job));
        }
    }
    for (const VoxelizeFrame& job : jobs) {
        checkOutputPath(job.output, "output", {job.input});
        if (!job.vti.empty()) checkOutputPath(job.vti, "--vti", {job.input, job.output});
    }
    std::optional<gpu::HeadlessContext> context; // made when the first frame needs it
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        if (frames.empty()) {
            voxelizeFrame(args, jobs[i], loadFrameScene(args, jobs[i]), method, context);
            continue;
        }
        try { // an error names its frame
            voxelizeFrame(args, jobs[i], loadFrameScene(args, jobs[i]), method, context);
        } catch (const CLI::Error&) {
            throw;
        } catch (const std::bad_alloc&) {
            throw;
        } catch (const std::exception& e) {
            throw Error(fmt::format("frame {} ('{}'): {}", frames[i], jobs[i].input, e.what()));
        }
    }
}

} // namespace

void addVoxelizeCommand(CLI::App& app) {
    auto args = std::make_shared<VoxelizeArgs>();
    CLI::App* cmd = app.add_subcommand("voxelize", "Voxelize a scene on the GPU into .vdb / .vti");
    cmd->add_option("scene", args->scene,
                    "Scene file (JSON, docs/scene-format.md) or a mesh (.obj, .ply, .glb, "
                    ".gltf: cubic voxels, grid fitted to its bounds)")
        ->required();
    cmd->add_option("-o,--output", args->output, "Output OpenVDB file (.vdb)")->required();
    cmd->add_option("--vti", args->vti, "Also write a VTK image (.vti) for ParaView");
    cmd->add_option("--res", args->res, "Columns per side of the grid camera")
        ->check(CLI::Range(1, 8192));
    cmd->add_option("--slices", args->slices, "Slices per column (default: --res)")
        ->check(CLI::Range(1, 65536));
    cmd->add_option("--method", args->method,
                    "raster | conservative | three-axis | compute (default: conservative; "
                    "raster with --solid)");
    cmd->add_flag("--solid", args->solid, "Solid voxelization (XOR of crossings, closed meshes)");
    cmd->add_flag("--local", args->local,
                  "Local slicing: per-column near/far from a range pass (raster, conservative)");
    cmd->add_flag("--perspective", args->perspective,
                  "Perspective grid from the scene camera (default: orthographic along +z)");
    cmd->add_option("--camera", args->camera, "Camera of --perspective (default: the first)");
    cmd->add_option("--smooth", args->smooth,
                    "Gaussian smoothing width in voxels for a soft fog density (default 0)")
        ->check(finiteRange(0.0, 64.0));
    cmd->add_option("--smooth-limit", args->smoothLimit,
                    "Refuse smoothing whose estimated voxel updates exceed this (0 = no limit; "
                    "default 5e9, about 25 s on 2 cores)")
        ->check(finiteRange(0.0, 1e18));
    // OpenVDB refuses scale maps whose determinant is below 3e-15 ("Non-zero scale values
    // required"), i.e. voxels under 1.4e-5; the bound leaves a margin.
    cmd->add_option("--voxel-size", args->voxelSize,
                    "World voxel size of resampled (perspective/local) grids (default: auto)")
        ->check(finiteRange(1e-4, 1e6));
    cmd->add_option("--set", args->overrides, "Override a scene value: key=value (repeatable)");
    cmd->add_option("--device", args->device, "EGL device index")->check(CLI::Range(0, 1023));
    cmd->add_flag("--quiet", args->quiet, "No progress bar");
    args->frames.add(*cmd, "the scene (time.frame) or of a mesh file sequence");
    cmd->callback([args] { runVoxelize(*args); });
}

} // namespace veil::app
