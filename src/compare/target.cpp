#include "compare/target.h"

#include "base/error.h"
#include "base/text.h"
#include "integrators/cpu_reference.h"
#include "integrators/medium.h"
#include "integrators/registry.h"
#include "io/image_io.h"

#include <filesystem>

namespace veil::compare {

namespace fs = std::filesystem;

CompareTarget parseCompareTarget(const std::string& text) {
    CompareTarget t;
    t.text = text;
    if (text.empty())
        t.kind = CompareTarget::Kind::None;
    else if (text == "cpu")
        t.kind = CompareTarget::Kind::Cpu;
    else if (text == "pathtraced")
        t.kind = CompareTarget::Kind::PathTraced;
    else if (text.rfind("shadows:", 0) == 0) {
        t.kind = CompareTarget::Kind::Shadows;
        t.shadows = text.substr(8);
    } else if (text.find_first_of("/.") != std::string::npos)
        t.kind = CompareTarget::Kind::File; // technique ids have neither
    else
        t.kind = CompareTarget::Kind::Technique;
    return t;
}

void checkCompareTarget(const CompareTarget& target, const scene::Scene& scene) {
    if (target.kind == CompareTarget::Kind::File) {
        std::error_code ec;
        VEIL_CHECK(fs::is_regular_file(target.text, ec),
                   "--compare-to '{}': no such image file (give an .exr, a technique or cpu)",
                   target.text);
        const std::string ext = lowerExtension(target.text);
        VEIL_CHECK(ext == ".exr" || ext == ".png" || ext == ".hdr" || ext == ".tif" ||
                       ext == ".tiff",
                   "--compare-to '{}': not an image (.exr; .png, .hdr and .tif are read too)",
                   target.text);
    } else if (target.kind == CompareTarget::Kind::Cpu ||
               target.kind == CompareTarget::Kind::PathTraced) {
        VEIL_CHECK(!scene.volumes.empty(),
                   "--compare-to {}: scene '{}' has no volumes (the reference renders the "
                   "volumes only)",
                   target.text, scene.sourcePath.string());
    }
}

ImageF loadReferenceImage(const CompareTarget& target, int width, int height) {
    ImageF image = io::readImage(target.text);
    VEIL_CHECK(image.channels >= 3, "--compare-to '{}': {} channel(s), need at least R, G, B",
               target.text, image.channels);
    VEIL_CHECK(image.width == width && image.height == height,
               "--compare-to '{}' is {}x{}, the render is {}x{} (use --width/--height)",
               target.text, image.width, image.height, width, height);
    return image;
}

ImageF cpuFogOverBackground(const scene::Scene& scene, const scene::Camera& camera, int width,
                            int height, int steps) {
    const volume::CpuFogReference reference(scene, volume::loadMediumGrids(scene));
    return reference.renderOverBackground(camera, width, height, steps);
}

ImageF cpuFogReference(const scene::Scene& scene, const std::string& camera, int width, int height,
                       std::string& note) {
    ImageF out = volume::IntegratorRegistry::instance()
                     .get("fog-march")
                     .render(scene, scene.camera(camera), width, height, {})
                     .radiance;
    note = scene.objects.empty()
               ? std::string()
               : fmt::format("note: the CPU reference is fog over the background only; the "
                             "scene's {} object(s) are not in it",
                             scene.objects.size());
    return out;
}

volume::PathTracerSettings pathTracedSettings(const scene::Scene& scene) {
    return volume::pathTracerSettings(scene);
}

volume::PathTracedImage pathTracedReference(const scene::Scene& scene,
                                            const volume::PathTracerSettings& settings,
                                            const std::string& camera, int width, int height,
                                            std::string& note,
                                            const std::function<void(int, int)>& progress) {
    const volume::VolumePathTracer tracer(scene, volume::loadMediumGrids(scene), settings);
    note = scene.objects.empty()
               ? std::string()
               : fmt::format("note: the path-traced reference has the volumes only; the "
                             "scene's {} object(s) are not in it",
                             scene.objects.size());
    return tracer.render(scene.camera(camera), width, height, [&](int done) {
        if (progress) progress(done, settings.spp);
        return true;
    });
}

} // namespace veil::compare
