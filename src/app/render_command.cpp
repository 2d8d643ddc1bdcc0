// `veil render <scene.json> -o out.{png,exr}`: one frame headless, plus a JSON report.
#include "app/cli_checks.h"
#include "app/commands.h"

#include "app/render_frames.h"
#include "app/render_integrator.h"
#include "base/progress.h"
#include "capture/dump.h"
#include "capture/exr_output.h"
#include "capture/frame_capture.h"
#include "capture/frame_output.h"
#include "compare/frame_compare.h"
#include "compare/sweep.h"
#include "compare/target.h"
#include "grid/vdb_scene.h"
#include "integrators/registry.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/suggest.h"
#include "base/text.h"
#include "frame/renderer.h"
#include "gpu/context.h"
#include "io/exr_writer.h"
#include "io/image_io.h"
#include "oit/technique.h"
#include "scene/scene.h"
#include "scene/scene_values.h"
#include "scene/timeline.h"
#include "shadows/technique.h"

#include <nlohmann/json.hpp>

#include <fmt/ranges.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>

namespace veil::app {

namespace fs = std::filesystem;

namespace {

struct RenderArgs {
    std::string scene;
    std::string output;
    std::string report;
    std::string camera;
    std::string oit;
    std::string shadows;
    int width = 0;
    int height = 0;
    int device = -1;
    bool glDebug = false;
    std::vector<std::string> overrides;
    std::string compareTo;
    bool half = false;             // EXR: half instead of float32 channels
    std::vector<std::string> aovs; // EXR: extra channels ("fog")
    std::string dump;              // folder for every frame resource (capture/dump.h)
    std::string grid;              // file.vdb: the density grid (name or index)
    bool progress = false;         // progress on stderr even when it is not a terminal
    std::string frames;            // frame range (render_frames.h)
    std::optional<int> frame;      // one frame of an animated scene
    bool resume = false;
    std::string integrator = "raster"; // raster (the GPU frame) or a CPU integrator by name
    double timeLimit = kDefaultIntegratorTimeLimit; // --integrator pathtraced: refuse longer work
};

// --frames / --frame: the options that go with one still frame are refused (usage errors).
void renderFrames(const RenderArgs& a) {
    if (a.frame && !a.frames.empty()) usageError("give --frames or --frame, not both");
    std::vector<std::string> still;
    if (!a.compareTo.empty()) still.push_back("--compare-to");
    if (!a.dump.empty()) still.push_back("--dump");
    if (!a.aovs.empty()) still.push_back("--aov");
    if (!a.grid.empty()) still.push_back("--grid");
    if (a.oit == "all") still.push_back("--oit all");
    if (a.shadows == "all") still.push_back("--shadows all");
    if (a.integrator != "raster") still.push_back("--integrator " + a.integrator);
    if (!still.empty())
        usageError(fmt::format(
            "--frames/--frame render the GPU frame of each frame of a scene; {} {} for one "
            "still frame{}",
            fmt::join(still, ", "), still.size() == 1 ? "is" : "are",
            a.integrator != "raster"
                ? fmt::format(" (render a frame with --integrator {} --set time.frame=N)",
                              a.integrator)
                : std::string()));
    if (lowerExtension(a.scene) == ".vdb")
        usageError(fmt::format("--frames/--frame render a scene file's frames, not the .vdb '{}' "
                               "(for a file sequence of .vdb files, write a scene whose volume "
                               "path is the pattern; docs/sequences.md)",
                               a.scene));
    runRenderFrames({a.scene, a.output, a.report, a.camera, a.oit, a.shadows, a.width, a.height,
                     a.device, a.glDebug, a.half, a.progress, a.resume, a.overrides, a.frames,
                     a.frame});
}

using Rendered = capture::RenderedFrame;

// The frame as --width, --height, --camera, --aov and --progress ask; `shadows` and
// `shadowProperties` replace --shadows (the --compare-to shadows:ID frame, --shadows all).
compare::FrameRender frameRender(const RenderArgs& args, const gpu::ContextInfo& info,
                                 bool dump = false) {
    return [&args, &info, dump](const scene::Scene& scene, const std::string& oit,
                                const std::string& shadows,
                                const nlohmann::json& shadowProperties) {
        capture::FrameRequest request;
        request.width = args.width;
        request.height = args.height;
        request.camera = args.camera;
        request.oit = oit;
        request.shadows = shadows.empty() ? args.shadows : shadows;
        request.shadowProperties = shadowProperties;
        request.fogAov = std::find(args.aovs.begin(), args.aovs.end(), "fog") != args.aovs.end();
        if (dump) request.dumpDir = args.dump;
        ProgressTicker ticker("rendering with " + oit +
                                  (shadows.empty() ? "" : ", shadows " + shadows),
                              progressWanted(args.progress));
        return capture::renderFrame(scene, info, request);
    };
}

// Fails before any rendering, naming the known techniques and where the name came from.
void checkKnown(const std::string& name, const std::string& where) {
    const auto& registry = oit::Registry::instance();
    VEIL_CHECK(registry.find(name), "{}: unknown OIT technique '{}'{} (known: {}{})", where, name,
               didYouMean(name, registry.names()), fmt::join(registry.names(), ", "),
               where == "--oit" ? ", or all" : "");
}

// The files one render writes (image, error image, report): when a later one cannot be
// written (a full disk), the earlier ones are removed, so a failed run leaves none of them.
class RunOutputs {
public:
    RunOutputs() = default;
    RunOutputs(const RunOutputs&) = delete;
    RunOutputs& operator=(const RunOutputs&) = delete;
    ~RunOutputs() {
        if (committed_) return;
        std::error_code ec;
        for (const fs::path& p : written_)
            fs::remove(p, ec);
    }
    void wrote(const fs::path& path) { written_.push_back(path); }
    void commit() { committed_ = true; }

private:
    std::vector<fs::path> written_;
    bool committed_ = false;
};

fs::path errorImagePath(const fs::path& output) {
    return output.parent_path() / (output.stem().string() + "-error.png");
}

// Arguments that cannot work together are usage errors (exit 2), found before any file is
// read; then every file the command will write is checked.
void checkArguments(const RenderArgs& args) {
    const std::string ext = lowerExtension(args.output);
    if (ext != ".png" && ext != ".exr")
        usageError(fmt::format("output '{}' must end in .png or .exr", args.output));
    // The report is optional: a default name beside the output could overwrite the scene.
    if (!args.report.empty() && lowerExtension(args.report) != ".json")
        usageError(fmt::format("report '{}' must end in .json", args.report));
    if (ext != ".exr" && (args.half || !args.aovs.empty()))
        usageError(fmt::format("--half and --aov need an .exr output, not '{}'", args.output));
    if (!args.dump.empty() && args.oit == "all")
        usageError("--dump needs one technique, not --oit all");
    if (!args.compareTo.empty() && args.oit == "all")
        usageError("--compare-to cannot be combined with --oit all (which compares every "
                   "technique with reference)");
    if (!args.grid.empty() && lowerExtension(args.scene) != ".vdb")
        usageError(fmt::format("--grid is for a .vdb input, not '{}'", args.scene));
    if (args.oit == "all" && args.shadows == "all")
        usageError("--oit all and --shadows all: one sheet at a time");
    if (args.integrator != "raster" &&
        (!args.compareTo.empty() || !args.dump.empty() || !args.aovs.empty() ||
         !args.report.empty() || args.half || args.oit == "all" || args.shadows == "all"))
        usageError(fmt::format(
            "--integrator {} writes the integrator's image (and a Monte Carlo one's standard "
            "error) only (no --compare-to, --dump, --aov, --half, --report, --oit all or "
            "--shadows all)",
            args.integrator));

    std::vector<fs::path> inputs{args.scene};
    if (compare::parseCompareTarget(args.compareTo).kind == compare::CompareTarget::Kind::File)
        inputs.push_back(args.compareTo); // -o ref.exr --compare-to ref.exr
    checkOutputPath(args.output, "output", inputs);
    if (args.integrator != "raster")
        checkOutputPath(standardErrorPath(args.output), "standard-error image", inputs);
    if (!args.report.empty()) checkOutputPath(args.report, "report", inputs);
    if (!args.compareTo.empty())
        checkOutputPath(errorImagePath(args.output), "error image", inputs);
    if (!args.dump.empty()) {
        if (args.shadows == "all") usageError("--dump needs one technique, not --shadows all");
        capture::checkDumpDirectory(args.dump);
    }
}

// The scene (or a .vdb framed as one) with --oit / --shadows chosen before --set, so
// render.oit.* / render.shadows.* reach them; an unknown name is named as the option's.
scene::Scene loadRenderScene(const RenderArgs& args, std::string& vdbNote) {
    const bool bareVdb = lowerExtension(args.scene) == ".vdb";
    VEIL_CHECK(bareVdb || args.grid.empty(), "--grid is for a .vdb input, not '{}'", args.scene);
    if (!args.oit.empty() && args.oit != "all") checkKnown(args.oit, "--oit");
    if (!args.shadows.empty() && args.shadows != "all")
        shadows::Registry::instance().get(args.shadows, "--shadows");
    const scene::TechniqueChoice choice{args.oit == "all" ? std::string() : args.oit,
                                        args.shadows == "all" ? std::string() : args.shadows};
    if (!bareVdb) return scene::loadScene(args.scene, args.overrides, choice);
    vdb::VdbScene v = vdb::sceneForVdb(args.scene, args.grid, args.overrides, choice);
    vdbNote = std::move(v.description);
    return std::move(v.scene);
}

// Bad technique names, properties and --compare-to targets fail here, before a context or an
// output exists.
void checkTechniques(const RenderArgs& args, const scene::Scene& scene, const std::string& oit,
                     const compare::CompareTarget& target) {
    const bool all = oit == "all", allShadows = args.shadows == "all";
    if (all && allShadows) usageError("--oit all and --shadows all: one sheet at a time");
    if (!all) {
        checkKnown(oit, args.oit.empty() ? scene.render.oitWhere + "/type" : "--oit");
        if (oit == scene.render.oit)
            oit::Registry::instance().resolve(oit, scene.render.oitProperties,
                                              scene.render.oitWhere);
    }
    shadows::Registry::instance().resolve(scene.render.shadows, scene.render.shadowProperties,
                                          scene.render.shadowsWhere);
    if (!args.compareTo.empty()) {
        if (all || allShadows)
            usageError("--compare-to cannot be combined with --oit all or --shadows all (which "
                       "compare every technique with reference)");
        if (target.kind == compare::CompareTarget::Kind::Technique)
            checkKnown(args.compareTo, "--compare-to");
        if (target.kind == compare::CompareTarget::Kind::Shadows)
            shadows::Registry::instance().get(target.shadows, "--compare-to");
        compare::checkCompareTarget(target, scene);
        if (target.kind == compare::CompareTarget::Kind::PathTraced)
            compare::pathTracedSettings(scene); // bad properties fail here
    }
    if (args.integrator != "raster") {
        VEIL_CHECK(!scene.volumes.empty(),
                   "--integrator {}: scene '{}' has no volumes (the CPU integrators render "
                   "volumes only)",
                   args.integrator, args.scene);
        if (args.integrator == "pathtraced")
            compare::pathTracedSettings(scene); // bad properties fail before anything renders
    }
}

// The report's common part: what was rendered, where, on what, with which scene values.
nlohmann::json renderReport(const RenderArgs& args, const scene::Scene& scene, const Rendered& main,
                            const std::string& oit, const gpu::ContextInfo& info,
                            const capture::RenderMetadata& metadata) {
    nlohmann::json report;
    report["scene"] = fs::absolute(args.scene).string();
    report["output"] = fs::absolute(args.output).string();
    report["width"] = main.width;
    report["height"] = main.height;
    report["camera"] = main.camera;
    report["oit"] = oit;
    if (args.shadows == "all") report["shadows"] = "all";
    report["renderer"] = info.renderer;
    report["gl_version"] = info.version;
    report["vendor"] = info.vendor;
    report["metadata"] = capture::metadataJson(metadata);
    // Every declared scene value as rendered (scene/scene_values.h), --width/--height included.
    report["scene_values"] = scene::sceneValues(scene);
    report["scene_values"]["render"]["width"] = main.width;
    report["scene_values"]["render"]["height"] = main.height;
    report["timer"] = main.timer == gpu::GpuTimer::Mode::Query
                          ? "GL_TIME_ELAPSED"
                          : "glFinish + CPU clock (driver timer unusable)";
    return report;
}

void runRender(const RenderArgs& args) {
    checkArguments(args);
    std::string vdbNote;
    const scene::Scene scene = loadRenderScene(args, vdbNote);
    const std::string oitName = args.oit.empty() ? scene.render.oit : args.oit;
    const compare::CompareTarget target = compare::parseCompareTarget(args.compareTo);
    checkTechniques(args, scene, oitName, target);
    if (args.integrator != "raster") {
        renderWithIntegrator(scene, args.integrator, args.camera, args.width, args.height,
                             args.output, args.progress, args.timeLimit);
        return;
    }
    const bool all = oitName == "all", allShadows = args.shadows == "all";
    const bool png = lowerExtension(args.output) == ".png";
    gpu::HeadlessContext context({args.device, args.glDebug});
    const gpu::ContextInfo& info = context.info();

    // Render everything first, write afterwards: a failing technique leaves no output.
    std::optional<compare::Sweep> sweep;
    std::optional<Rendered> single;
    std::optional<compare::FrameComparison> comparison;
    if (all || allShadows) {
        sweep = compare::runSweep(all ? compare::SweepKind::Oit : compare::SweepKind::Shadows,
                                  scene, oitName, info, frameRender(args, info),
                                  [](const std::string& line) { std::cout << line << "\n"; });
    } else {
        single = frameRender(args, info, !args.dump.empty())(scene, oitName, {}, {});
        if (target.kind != compare::CompareTarget::Kind::None)
            comparison = compare::compareFrame(target, scene, *single,
                                               {oitName, args.camera, args.output, args.progress},
                                               frameRender(args, info));
    }
    const Rendered& main = sweep ? sweep->frames.front() : *single;
    const std::string oitLabel = all ? std::string("all") : main.oit;
    const capture::RenderMetadata metadata =
        capture::describeRender(args.scene, oitLabel, main.oitProperties, main.camera, main.extras,
                                main.width, main.height, info.renderer);

    // PNG gets the tone-mapped sRGB image, EXR the linear HDR radiance.
    RunOutputs outputs;
    const fs::path errorPath = errorImagePath(args.output);
    if (sweep && png)
        io::writeImage(args.output, compare::sweepContactSheet(*sweep));
    else if (sweep)
        io::writeExr(args.output, compare::sweepExr(*sweep, metadata, args.half));
    else
        capture::writeFrame(args.output, main, metadata, args.half);
    outputs.wrote(args.output);
    if (comparison) {
        io::writeImage(errorPath, compare::errorImage(comparison->compared, comparison->reference));
        outputs.wrote(errorPath);
    }

    nlohmann::json report = renderReport(args, scene, main, oitLabel, info, metadata);
    if (sweep) {
        report["techniques"] = compare::sweepTechniques(*sweep);
        report["sheet_order"] =
            png ? "in rows, left to right, as in techniques[]; each tile labelled with its "
                  "technique, RMSE against reference and GPU time"
                : "EXR: reference in R,G,B,A,Z, the others as layers <technique>.R,G,B (header "
                  "veil:layers)";
    } else {
        report.update(capture::frameReport(main));
        if (comparison) {
            report["compare"] = compare::errorJson(args.compareTo, comparison->error);
            report["compare"]["error_image"] = fs::absolute(errorPath).string();
            report["compare"]["error_image_scale"] = compare::kErrorImageScale;
            if (!comparison->note.empty()) report["compare"]["note"] = comparison->note;
        }
    }
    if (!args.report.empty()) {
        writeTextFileAtomically(
            args.report,
            report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
    }
    outputs.commit();
    if (sweep) {
        std::cout << "wrote " << args.output << " ("
                  << (png ? "contact sheet, " + std::to_string(sweep->frames.size()) + " tiles of "
                          : std::to_string(sweep->frames.size()) + " techniques as EXR layers of ")
                  << main.width << "x" << main.height << ", " << info.renderer << ")\n"
                  << compare::sweepSummary(*sweep);
    } else {
        if (!vdbNote.empty()) std::cout << vdbNote << "\n";
        std::cout << "wrote " << args.output << " (" << main.width << "x" << main.height << ", oit "
                  << main.oit << ", " << info.renderer << ")\n";
        if (comparison && !comparison->note.empty()) std::cout << comparison->note << "\n";
        if (comparison)
            std::cout << fmt::format(
                "{} vs {}: {} (linear HDR)\nwrote {} (|error| x {} in linear, sRGB-encoded)\n",
                target.kind == compare::CompareTarget::Kind::Shadows ? "shadows:" + main.shadows
                                                                     : main.oit,
                args.compareTo, compare::formatError(comparison->error), errorPath.string(),
                compare::kErrorImageScale);
    }
    if (!args.report.empty()) std::cout << "wrote " << args.report << " (per-pass GPU times)\n";
    if (!args.dump.empty())
        std::cout << "wrote " << (fs::path(args.dump) / "manifest.json").string() << " ("
                  << main.dumpManifest["resources"].size() << " frame resources)\n";
}

} // namespace

void addRenderCommand(CLI::App& app) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* cmd = app.add_subcommand("render", "Render a scene headless to PNG or EXR");
    cmd->add_option("scene", args->scene,
                    "Scene file (JSON, docs/scene-format.md), or an OpenVDB file (.vdb) framed "
                    "with a default camera and light")
        ->required();
    cmd->add_option("--grid", args->grid,
                    ".vdb input: the density grid, by name or index (default: the first float "
                    "grid)");
    cmd->add_option("-o,--output", args->output,
                    "Output image: .png (tone-mapped sRGB) or .exr (float32 R,G,B,A,Z + metadata; "
                    "A = 1, Z = view depth of the opaque surface, +inf for none)")
        ->required();
    cmd->add_flag("--half", args->half,
                  "EXR: half-float channels (rounded to nearest) instead of float32");
    cmd->add_option("--aov", args->aovs,
                    "EXR: extra channels; 'fog' adds fog.R/G/B (fog radiance) and "
                    "fog.transmittance (repeatable)")
        ->check(CLI::IsMember({"fog"}));
    cmd->add_option("--dump", args->dump,
                    "Write every frame resource into this folder: 2D textures as float32 EXR, 3D "
                    "as .vti, and manifest.json (file, resource, size, format, units)");
    cmd->add_flag("--progress", args->progress,
                  "Show progress on stderr for frames over 2 s even when stderr is not a "
                  "terminal (on a terminal it is always shown)");
    cmd->add_option("--report", args->report,
                    "Also write a JSON report: per-pass GPU times, image size, renderer, errors");
    cmd->add_option("--width", args->width, "Image width (default: the scene's)")
        ->check(CLI::Range(1, 16384));
    cmd->add_option("--height", args->height, "Image height (default: the scene's)")
        ->check(CLI::Range(1, 16384));
    cmd->add_option("--camera", args->camera, "Camera name (default: the scene's)");
    cmd->add_option("--oit", args->oit,
                    "Transparency technique (default: the scene's); 'all' renders every "
                    "available one into a contact sheet (PNG) or EXR layers <technique>.R/G/B "
                    "beside the reference's R,G,B,A,Z, and prints each one's error vs reference");
    cmd->add_option("--shadows", args->shadows,
                    "Shadow technique (default: the scene's render.shadows; see `veil "
                    "techniques`); 'all' renders every available one into a contact sheet and "
                    "prints each one's error vs the reference shadows");
    cmd->add_option(
        "--compare-to", args->compareTo,
        "Compare the output (linear HDR RGB) with: a technique (e.g. reference, "
        "rendered too), shadows:ID (the same frame with that shadow technique, e.g. "
        "shadows:reference), an image file (e.g. ref.exr, same size), cpu (the fog's "
        "CPU reference over the background; scenes with volumes) or pathtraced (the volumetric "
        "path tracer, render.pathtraced.*). Prints RMSE/PSNR, "
        "writes <output stem>-error.png (|error| x 4)");
    std::vector<std::string> integrators{"raster"};
    for (const std::string& name : volume::IntegratorRegistry::instance().names())
        integrators.push_back(name);
    cmd->add_option("--integrator", args->integrator,
                    "raster: the GPU frame; or a CPU integrator's image of the volumes "
                    "(src/integrators): pathtraced, the volumetric path tracer "
                    "(render.pathtraced.spp, max_bounces, seed, roulette_depth, batch), plus "
                    "<output stem>-stderr.exr with the per-pixel standard error; fog-march, "
                    "the fog marcher's CPU reference")
        ->check(CLI::IsMember(integrators));
    cmd->add_option("--time-limit", args->timeLimit,
                    "--integrator pathtraced: refuse a render estimated (from timed samples "
                    "before it starts, then from each pass) to take longer than this many "
                    "seconds (0 = no limit; default 3600)")
        ->check(finiteRange(0.0, 1e9));
    cmd->add_option("--set", args->overrides,
                    "Override a scene value: key=value, e.g. render.exposure=2 or "
                    "lights.0.intensity=5 (repeatable)");
    cmd->add_option("--device", args->device,
                    "EGL device index (default: $VEIL_EGL_DEVICE, else the first that works)")
        ->check(CLI::Range(0, 1023));
    cmd->add_flag("--gl-debug", args->glDebug, "Debug context; GL messages go to the log");
    cmd->add_option("--frames", args->frames,
                    "Render frames FIRST-LAST[:STEP] of an animated scene (sequences, camera "
                    "keys, turntable) in one process; -o needs a frame pattern "
                    "(out.####.exr, out.%04d.png, out.$F4.exr) or ends in .mp4 (ffmpeg)")
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                try {
                    scene::parseFrameRange(text);
                } catch (const Error& e) {
                    const std::string m = e.what(); // CLI11 names the option itself
                    return m.rfind("--frames ", 0) == 0 ? m.substr(9) : m;
                }
                return {};
            },
            "FIRST-LAST[:STEP]"));
    cmd->add_option("--frame", args->frame, "Render this one frame of an animated scene");
    cmd->add_flag("--resume", args->resume, "--frames: skip frames whose output image is complete");
    cmd->callback([args] {
        if (!args->frames.empty() || args->frame)
            renderFrames(*args);
        else {
            if (args->resume) usageError("--resume goes with --frames (skip complete frames)");
            runRender(*args);
        }
    });
}

} // namespace veil::app
