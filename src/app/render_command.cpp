// `veil render <scene.json> -o out.{png,exr}`: one frame headless, plus a JSON report.
#include "app/commands.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "frame/renderer.h"
#include "gpu/context.h"
#include "io/image_io.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

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
    int width = 0;
    int height = 0;
    int device = -1;
    bool glDebug = false;
    std::vector<std::string> overrides;
};

void runRender(const RenderArgs& args) {
    std::string ext = fs::path(args.output).extension().string();
    VEIL_CHECK(ext == ".png" || ext == ".exr", "output '{}' must end in .png or .exr",
               args.output);
    if (!args.report.empty()) {
        VEIL_CHECK(fs::path(args.report).extension() == ".json", "report '{}' must end in .json",
                   args.report);
        std::error_code ec;
        VEIL_CHECK(!fs::equivalent(args.report, args.scene, ec),
                   "report '{}' would overwrite the scene file", args.report);
    }
    scene::Scene scene = scene::loadScene(args.scene, args.overrides);
    gpu::HeadlessContext context({args.device, args.glDebug});
    frame::RendererOptions options{args.width, args.height, args.camera, args.oit};
    frame::Renderer renderer(scene, context.info(), options);
    renderer.render();

    // PNG gets the tone-mapped sRGB image, EXR the linear HDR radiance.
    const ImageF image = ext == ".png" ? renderer.readLdr() : renderer.readHdr();
    io::writeImage(args.output, image);

    nlohmann::json report;
    report["scene"] = fs::absolute(args.scene).string();
    report["output"] = fs::absolute(args.output).string();
    report["width"] = renderer.width();
    report["height"] = renderer.height();
    report["camera"] = renderer.camera().name;
    report["oit"] = renderer.oitName();
    report["renderer"] = context.info().renderer;
    report["gl_version"] = context.info().version;
    report["vendor"] = context.info().vendor;
    report["timer"] = renderer.timerMode() == gpu::GpuTimer::Mode::Query
                          ? "GL_TIME_ELAPSED"
                          : "glFinish + CPU clock (driver timer unusable)";
    report["gpu_bytes"] = renderer.gpuBytes();
    double total = 0.0;
    nlohmann::json passes = nlohmann::json::array();
    for (const auto& p : renderer.passTimes()) {
        passes.push_back({{"name", p.name}, {"ms", p.milliseconds}});
        total += p.milliseconds;
    }
    report["passes"] = passes;
    report["total_ms"] = total;
    std::cout << "wrote " << args.output << " (" << renderer.width() << "x" << renderer.height()
              << ", oit " << renderer.oitName() << ", " << context.info().renderer << ")\n";
    if (args.report.empty()) return;
    const fs::path reportPath = args.report;
    writeFileAtomically(reportPath, [&](const fs::path& tmp) {
        std::ofstream out(tmp);
        out << report.dump(2) << "\n";
        VEIL_CHECK(out.good(), "cannot write report '{}'", reportPath.string());
    });
    std::cout << "wrote " << reportPath.string() << " (per-pass GPU times)\n";
}

} // namespace

void addRenderCommand(CLI::App& app) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* cmd = app.add_subcommand("render", "Render a scene headless to PNG or EXR");
    cmd->add_option("scene", args->scene, "Scene file (JSON, docs/scene-format.md)")
        ->required();
    cmd->add_option("-o,--output", args->output,
                    "Output image: .png (tone-mapped sRGB) or .exr (linear HDR)")
        ->required();
    cmd->add_option("--report", args->report,
                    "Also write a JSON report: per-pass GPU times, image size, renderer");
    cmd->add_option("--width", args->width, "Image width (default: the scene's)")
        ->check(CLI::Range(1, 16384));
    cmd->add_option("--height", args->height, "Image height (default: the scene's)")
        ->check(CLI::Range(1, 16384));
    cmd->add_option("--camera", args->camera, "Camera name (default: the scene's)");
    cmd->add_option("--oit", args->oit, "Transparency technique (default: the scene's)");
    cmd->add_option("--set", args->overrides,
                    "Override a scene value: key=value, e.g. render.exposure=2 or "
                    "lights.0.intensity=5 (repeatable)");
    cmd->add_option("--device", args->device,
                    "EGL device index (default: $VEIL_EGL_DEVICE, else the first that works)");
    cmd->add_flag("--gl-debug", args->glDebug, "Debug context; GL messages go to the log");
    cmd->callback([args] { runRender(*args); });
}

} // namespace veil::app
