// `veil render <scene.json> -o out.{png,exr}`: one frame headless, plus a JSON report.
#include "app/cli_checks.h"
#include "app/commands.h"

#include "app/progress.h"
#include "app/render_frames.h"
#include "app/render_pathtraced.h"
#include "capture/dump.h"
#include "capture/exr_output.h"
#include "capture/frame_capture.h"
#include "compare/compare.h"
#include "compare/target.h"
#include "vdb/vdb_scene.h"

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
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>

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
    std::string integrator = "raster"; // raster (the GPU frame) or pathtraced (render_pathtraced.h)
};

// --frames / --frame: the options that go with one still frame are refused.
void renderFrames(const RenderArgs& a) {
    VEIL_CHECK(a.compareTo.empty() && a.dump.empty() && a.aovs.empty() && a.grid.empty() &&
                   a.oit != "all" && lowerExtension(a.scene) != ".vdb",
               "--frames/--frame render a scene file's frames; --compare-to, --dump, --aov, "
               "--grid, --oit all and .vdb inputs are for one still frame");
    runRenderFrames({a.scene, a.output, a.report, a.camera, a.oit, a.shadows, a.width, a.height,
                     a.device, a.glDebug, a.half, a.progress, a.resume, a.overrides, a.frames,
                     a.frame});
}

using Rendered = capture::RenderedFrame;

// `shadows` / `shadowProperties` replace --shadows (the --compare-to shadows:ID frame).
Rendered renderWith(const scene::Scene& scene, const gpu::ContextInfo& info, const RenderArgs& args,
                    const std::string& oit, bool dump = false, const std::string& shadows = {},
                    const nlohmann::json& shadowProperties = {}) {
    capture::FrameRequest request;
    request.width = args.width;
    request.height = args.height;
    request.camera = args.camera;
    request.oit = oit;
    request.shadows = shadows.empty() ? args.shadows : shadows;
    request.shadowProperties = shadowProperties;
    request.fogAov = std::find(args.aovs.begin(), args.aovs.end(), "fog") != args.aovs.end();
    if (dump) request.dumpDir = args.dump;
    ProgressTicker ticker("rendering with " + oit, progressWanted(args.progress));
    return capture::renderFrame(scene, info, request);
}

// Fails before any rendering, naming the known techniques and where the name came from.
void checkKnown(const std::string& name, const std::string& where) {
    const auto& registry = oit::Registry::instance();
    VEIL_CHECK(registry.find(name), "{}: unknown OIT technique '{}'{} (known: {}{})", where, name,
               didYouMean(name, registry.names()), fmt::join(registry.names(), ", "),
               where == "--oit" ? ", or all" : "");
}

nlohmann::json errorJson(const std::string& against, const compare::ImageError& e) {
    // JSON has no infinity: an identical image has "psnr_db": "inf".
    nlohmann::json j = {{"against", against}, {"rmse", e.rmse}, {"peak", e.peak}};
    if (std::isfinite(e.psnr))
        j["psnr_db"] = e.psnr;
    else
        j["psnr_db"] = std::isinf(e.psnr) ? "inf" : "undefined";
    j["metric"] = "linear HDR RGB; RMSE = sqrt(mean (a-b)^2); PSNR = 10 log10(peak^2 / MSE), "
                  "peak = max RGB of the reference";
    return j;
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

std::string formatError(const compare::ImageError& e) {
    return fmt::format("RMSE {:.6g}, PSNR {} (peak {:.4g})", e.rmse,
                       std::isfinite(e.psnr) ? fmt::format("{:.2f} dB", e.psnr)
                                             : std::string(std::isinf(e.psnr) ? "inf" : "n/a"),
                       e.peak);
}

// Every file the command will write, checked before the scene is loaded or rendered.
void checkOutputPaths(const RenderArgs& args) {
    std::vector<fs::path> inputs{args.scene};
    if (compare::parseCompareTarget(args.compareTo).kind == compare::CompareTarget::Kind::File)
        inputs.push_back(args.compareTo); // -o ref.exr --compare-to ref.exr

    checkOutputPath(args.output, "output", inputs);
    if (args.integrator == "pathtraced")
        checkOutputPath(pathTracedErrorPath(args.output), "standard-error image", inputs);
    if (!args.report.empty()) checkOutputPath(args.report, "report", inputs);
    if (!args.compareTo.empty())
        checkOutputPath(errorImagePath(args.output), "error image", inputs);
}

void runRender(const RenderArgs& args) {
    const fs::path output = args.output;
    std::string ext = lowerExtension(args.output);
    // Arguments that cannot work together are usage errors (exit 2), found before any file
    // is read.
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
    checkOutputPaths(args);
    if (!args.dump.empty()) {
        VEIL_CHECK(args.oit != "all" && args.shadows != "all",
                   "--dump needs one technique, not all");
        capture::checkDumpDirectory(args.dump);
    }
    const bool bareVdb = lowerExtension(args.scene) == ".vdb";
    VEIL_CHECK(bareVdb || args.grid.empty(), "--grid is for a .vdb input, not '{}'", args.scene);
    std::string vdbNote;
    scene::Scene scene;
    // --oit / --shadows choose before --set, so render.oit.* / render.shadows.* reach them; an
    // unknown name is named as the option's.
    if (!args.oit.empty() && args.oit != "all") checkKnown(args.oit, "--oit");
    if (!args.shadows.empty() && args.shadows != "all")
        shadows::Registry::instance().get(args.shadows, "--shadows");
    const scene::TechniqueChoice choice{args.oit == "all" ? std::string() : args.oit,
                                        args.shadows == "all" ? std::string() : args.shadows};
    if (bareVdb) {
        vdb::VdbScene v = vdb::sceneForVdb(args.scene, args.grid, args.overrides, choice);
        scene = std::move(v.scene);
        vdbNote = std::move(v.description);
    } else {
        scene = scene::loadScene(args.scene, args.overrides, choice);
    }
    const std::string oitName = args.oit.empty() ? scene.render.oit : args.oit;
    const bool all = oitName == "all";
    // --shadows all: every shadow technique with the same OIT, against the reference shadows.
    const bool allShadows = args.shadows == "all";
    VEIL_CHECK(!all || !allShadows, "--oit all and --shadows all: one sheet at a time");
    if (!all) {
        checkKnown(oitName, args.oit.empty() ? scene.render.oitWhere + "/type" : "--oit");
        // Bad property names or values fail here, before a context or an output exists.
        if (oitName == scene.render.oit)
            oit::Registry::instance().resolve(oitName, scene.render.oitProperties,
                                              scene.render.oitWhere);
    }
    shadows::Registry::instance().resolve(scene.render.shadows, scene.render.shadowProperties,
                                          scene.render.shadowsWhere);
    const compare::CompareTarget compareTarget = compare::parseCompareTarget(args.compareTo);
    if (!args.compareTo.empty()) {
        VEIL_CHECK(!all && !allShadows,
                   "--compare-to cannot be combined with --oit all or --shadows all (which "
                   "compare every technique with reference)");
        if (compareTarget.kind == compare::CompareTarget::Kind::Technique)
            checkKnown(args.compareTo, "--compare-to");
        if (compareTarget.kind == compare::CompareTarget::Kind::Shadows)
            shadows::Registry::instance().get(compareTarget.shadows, "--compare-to");
        compare::checkCompareTarget(compareTarget, scene);
        if (compareTarget.kind == compare::CompareTarget::Kind::PathTraced)
            compare::pathTracedSettings(args.scene, args.overrides); // bad properties fail here
    }
    if (args.integrator == "pathtraced") {
        VEIL_CHECK(args.compareTo.empty() && args.dump.empty() && args.aovs.empty() &&
                       args.report.empty() && !args.half && !all,
                   "--integrator pathtraced writes the path-traced image and its standard error "
                   "only (no --compare-to, --dump, --aov, --half, --report or --oit all)");
        VEIL_CHECK(!scene.volumes.empty(),
                   "--integrator pathtraced: scene '{}' has no volumes (the path tracer renders "
                   "volumes only)",
                   args.scene);
        renderPathTraced(scene, compare::pathTracedSettings(args.scene, args.overrides),
                         args.camera, args.width, args.height, output, args.progress);
        return;
    }
    gpu::HeadlessContext context({args.device, args.glDebug});
    const bool png = ext == ".png";

    // Render everything first, write afterwards: a failing technique leaves no output.
    std::vector<Rendered> frames;
    std::vector<std::pair<std::string, compare::ImageError>> errors;
    ImageF referenceHdr; // what --compare-to compares with
    ImageF comparedHdr;  // what is compared with it: the frame, or for cpu its fog only
    std::string compareNote;
    if (all) {
        frames.push_back(renderWith(scene, context.info(), args, "reference"));
        for (const auto& t : oit::Registry::instance().all()) {
            if (t.name == "reference") continue;
            if (t.isAvailable && !t.isAvailable(context.info())) {
                std::cout << "skipping " << t.name << " (not available on "
                          << context.info().renderer << ")\n";
                continue;
            }
            frames.push_back(renderWith(scene, context.info(), args, t.name));
        }
        for (const Rendered& f : frames)
            errors.emplace_back(f.oit, compare::compareLinear(f.hdr, frames.front().hdr));
    } else if (allShadows) {
        frames.push_back(renderWith(scene, context.info(), args, oitName, false, "reference"));
        // Every technique at the reference's map size (other properties at their defaults).
        const nlohmann::json size = {{"size", frames.front().shadowProperties.at("size")}};
        for (const auto& t : shadows::Registry::instance().all()) {
            if (t.name == "reference") continue;
            if (t.isAvailable && !t.isAvailable(context.info())) {
                std::cout << "skipping shadows " << t.name << " (not available on "
                          << context.info().renderer << ")\n";
                continue;
            }
            frames.push_back(renderWith(scene, context.info(), args, oitName, false, t.name, size));
        }
        for (const Rendered& f : frames)
            errors.emplace_back("shadows:" + f.shadows,
                                compare::compareLinear(f.hdr, frames.front().hdr));
    } else {
        frames.push_back(renderWith(scene, context.info(), args, oitName, !args.dump.empty()));
        const Rendered& f = frames.front();
        if (compareTarget.kind == compare::CompareTarget::Kind::Technique)
            referenceHdr = renderWith(scene, context.info(), args, args.compareTo).hdr;
        else if (compareTarget.kind == compare::CompareTarget::Kind::Shadows)
            // The same frame and OIT technique with the other shadow technique at the same
            // map size (its other properties at their defaults).
            referenceHdr =
                renderWith(scene, context.info(), args, oitName, false, compareTarget.shadows,
                           {{"size", f.shadowProperties.at("size")}})
                    .hdr;
        else if (compareTarget.kind == compare::CompareTarget::Kind::File)
            referenceHdr = compare::loadReferenceImage(compareTarget, f.width, f.height);
        else if (compareTarget.kind == compare::CompareTarget::Kind::Cpu) {
            // The CPU reference holds the fog only: a scene with surfaces is rendered a second
            // time without them (nor the shadows they cast), and that frame is compared.
            if (!scene.objects.empty()) {
                scene::Scene fogOnly = scene;
                fogOnly.objects.clear();
                comparedHdr = renderWith(fogOnly, context.info(), args, oitName).hdr;
                ProgressTicker ticker("CPU fog reference", progressWanted(args.progress));
                std::string unused;
                referenceHdr =
                    compare::cpuFogReference(fogOnly, args.camera, f.width, f.height, unused);
                compareNote = fmt::format(
                    "compared: the fog alone (the frame rendered again without the scene's {} "
                    "object(s) and their shadows) against the CPU fog reference; {} is the "
                    "whole scene",
                    scene.objects.size(), args.output);
            } else {
                ProgressTicker ticker("CPU fog reference", progressWanted(args.progress));
                referenceHdr =
                    compare::cpuFogReference(scene, args.camera, f.width, f.height, compareNote);
                compareNote = "compared: the fog (the scene has no surfaces) against the CPU fog "
                              "reference";
            }
        } else if (compareTarget.kind == compare::CompareTarget::Kind::PathTraced) {
            ProgressTicker ticker("path-traced reference", progressWanted(args.progress));
            referenceHdr = compare::pathTracedReference(
                               scene, compare::pathTracedSettings(args.scene, args.overrides),
                               args.camera, f.width, f.height, compareNote)
                               .radiance;
        }
        if (comparedHdr.pixels.empty()) comparedHdr = f.hdr;
        if (compareTarget.kind != compare::CompareTarget::Kind::None)
            errors.emplace_back(f.oit, compare::compareLinear(comparedHdr, referenceHdr));
    }
    const Rendered& main = frames.front();
    const capture::RenderMetadata metadata = capture::describeRender(
        args.scene, all ? std::string("all") : main.oit, main.oitProperties, main.camera,
        main.extras, main.width, main.height, context.info().renderer);

    // PNG gets the tone-mapped sRGB image, EXR the linear HDR radiance.
    fs::path errorPath;
    RunOutputs outputs;
    if ((all || allShadows) && png) {
        std::vector<ImageF> tiles;
        std::vector<std::vector<std::string>> labels;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            tiles.push_back(frames[i].ldr);
            labels.push_back({allShadows ? "shadows " + frames[i].shadows : frames[i].oit,
                              i == 0 ? std::string("RMSE 0 (exact)")
                                     : fmt::format("RMSE {:.4f}", errors[i].second.rmse),
                              fmt::format("GPU {:.1f} ms", frames[i].totalMs)});
        }
        io::writeImage(output, compare::labelledContactSheet(tiles, labels));
        outputs.wrote(output);
    } else if (all || allShadows) {
        // EXR: the reference frame as R, G, B, A, Z (and --aov channels, --half), every other
        // technique as a layer <technique>.R/.G/.B of the same size, not a contact sheet.
        io::ExrImage exr = capture::makeExr(main.hdr, main.extras, metadata, args.half);
        const auto name = [&](const Rendered& f) {
            return allShadows ? "shadows-" + f.shadows : f.oit;
        };
        std::string layers = "R,G,B,A,Z: " + name(main);
        for (std::size_t i = 1; i < frames.size(); ++i) {
            capture::addRgbLayer(exr, name(frames[i]), frames[i].hdr);
            layers += "; " + name(frames[i]) + ".R,G,B: " + name(frames[i]);
        }
        exr.strings.emplace_back("veil:layers", layers);
        io::writeExr(output, exr);
        outputs.wrote(output);
    } else {
        if (png)
            io::writeImage(output, main.ldr);
        else
            io::writeExr(output, capture::makeExr(main.hdr, main.extras, metadata, args.half));
        outputs.wrote(output);
        if (!args.compareTo.empty()) {
            errorPath = errorImagePath(output);
            io::writeImage(errorPath, compare::errorImage(comparedHdr, referenceHdr));
            outputs.wrote(errorPath);
        }
    }

    nlohmann::json report;
    report["scene"] = fs::absolute(args.scene).string();
    report["output"] = fs::absolute(args.output).string();
    report["width"] = main.width;
    report["height"] = main.height;
    report["camera"] = main.camera;
    report["oit"] = all ? std::string("all") : main.oit;
    if (allShadows) report["shadows"] = "all";
    report["renderer"] = context.info().renderer;
    report["gl_version"] = context.info().version;
    report["vendor"] = context.info().vendor;
    report["metadata"] = capture::metadataJson(metadata);
    // Every declared scene value as rendered (scene/scene_values.h), --width/--height included.
    report["scene_values"] = scene::sceneValues(scene);
    report["scene_values"]["render"]["width"] = main.width;
    report["scene_values"]["render"]["height"] = main.height;
    report["timer"] = main.timer == gpu::GpuTimer::Mode::Query
                          ? "GL_TIME_ELAPSED"
                          : "glFinish + CPU clock (driver timer unusable)";
    if (all || allShadows) {
        nlohmann::json techniques = nlohmann::json::array();
        for (std::size_t i = 0; i < frames.size(); ++i) {
            const Rendered& f = frames[i];
            techniques.push_back(
                {{"oit", f.oit},
                 {"shadows", f.shadows},
                 {"gpu_bytes", f.gpuBytes},
                 {"passes", f.passes},
                 {"total_ms", f.totalMs},
                 {"oit_stats", f.oitStats},
                 {"oit_properties", f.oitProperties},
                 {"compare",
                  errorJson(allShadows ? "shadows:reference" : "reference", errors[i].second)}});
        }
        report["techniques"] = techniques;
        report["sheet_order"] =
            png ? "in rows, left to right, as in techniques[]; each tile labelled with its "
                  "technique, RMSE against reference and GPU time"
                : "EXR: reference in R,G,B,A,Z, the others as layers <technique>.R,G,B (header "
                  "veil:layers)";
    } else {
        report.update(capture::frameReport(main));
        if (!args.compareTo.empty()) {
            report["compare"] = errorJson(args.compareTo, errors.front().second);
            report["compare"]["error_image"] = fs::absolute(errorPath).string();
            report["compare"]["error_image_scale"] = compare::kErrorImageScale;
            if (!compareNote.empty()) report["compare"]["note"] = compareNote;
        }
    }
    const fs::path reportPath = args.report;
    if (!args.report.empty()) {
        writeTextFileAtomically(
            reportPath,
            report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
    }
    outputs.commit();
    if ((all || allShadows) && !png) {
        std::cout << "wrote " << args.output << " (" << frames.size()
                  << " techniques as EXR layers "
                  << "of " << main.width << "x" << main.height << ", " << context.info().renderer
                  << ")\n";
        for (const auto& [name, e] : errors)
            std::cout << fmt::format("  {:<12} vs {}reference: {}\n", name,
                                     allShadows ? "shadows:" : "", formatError(e));
    } else if (all || allShadows) {
        std::cout << "wrote " << args.output << " (contact sheet, " << frames.size() << " tiles of "
                  << main.width << "x" << main.height << ", " << context.info().renderer << ")\n";
        for (const auto& [name, e] : errors)
            std::cout << fmt::format("  {:<12} vs {}reference: {}\n", name,
                                     allShadows ? "shadows:" : "", formatError(e));
    } else {
        if (!vdbNote.empty()) std::cout << vdbNote << "\n";
        std::cout << "wrote " << args.output << " (" << main.width << "x" << main.height << ", oit "
                  << main.oit << ", " << context.info().renderer << ")\n";
        if (!compareNote.empty()) std::cout << compareNote << "\n";
        if (!args.compareTo.empty())
            std::cout << fmt::format("{} vs {}: {} (linear HDR)\nwrote {} (|error| x {} in "
                                     "linear, sRGB-encoded)\n",
                                     compareTarget.kind == compare::CompareTarget::Kind::Shadows
                                         ? "shadows:" + main.shadows
                                         : main.oit,
                                     args.compareTo, formatError(errors.front().second),
                                     errorPath.string(), compare::kErrorImageScale);
    }
    if (!args.report.empty())
        std::cout << "wrote " << reportPath.string() << " (per-pass GPU times)\n";
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
    cmd->add_option("--integrator", args->integrator,
                    "raster: the GPU frame; pathtraced: the volumetric path tracer's image of the "
                    "volumes (render.pathtraced.spp, max_bounces, seed, roulette_depth, batch), "
                    "plus <output stem>-stderr.exr with the per-pixel standard error")
        ->check(CLI::IsMember({"raster", "pathtraced"}));
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
                    return e.what();
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
            VEIL_CHECK(!args->resume, "--resume goes with --frames");
            runRender(*args);
        }
    });
}

} // namespace veil::app
