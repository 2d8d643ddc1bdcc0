// A frame against its --compare-to target (frame_compare.h).
#include "compare/frame_compare.h"

#include "base/progress.h"

#include <fmt/format.h>

namespace veil::compare {

FrameComparison compareFrame(const CompareTarget& target, const scene::Scene& scene,
                             const capture::RenderedFrame& frame,
                             const FrameCompareRequest& request, const FrameRender& render) {
    using Kind = CompareTarget::Kind;
    FrameComparison c;
    const bool progress = progressWanted(request.progress);
    if (target.kind == Kind::Technique) {
        c.reference = render(scene, target.text, {}, {}).hdr;
    } else if (target.kind == Kind::Shadows) {
        // The same frame and OIT technique with the other shadow technique at the same map
        // size (its other properties at their defaults).
        c.reference = render(scene, request.oit, target.shadows,
                             {{"size", frame.shadowProperties.at("size")}})
                          .hdr;
    } else if (target.kind == Kind::File) {
        c.reference = loadReferenceImage(target, frame.width, frame.height);
    } else if (target.kind == Kind::Cpu) {
        // The CPU reference holds the fog only: a scene with surfaces is rendered a second
        // time without them (nor the shadows they cast), and that frame is compared.
        if (!scene.objects.empty()) {
            scene::Scene fogOnly = scene;
            fogOnly.objects.clear();
            c.compared = render(fogOnly, request.oit, {}, {}).hdr;
            ProgressTicker ticker("CPU fog reference", progress);
            std::string unused;
            c.reference =
                cpuFogReference(fogOnly, request.camera, frame.width, frame.height, unused);
            c.note = fmt::format(
                "compared: the fog alone (the frame rendered again without the scene's {} "
                "object(s) and their shadows) against the CPU fog reference; {} is the "
                "whole scene",
                scene.objects.size(), request.output);
        } else {
            ProgressTicker ticker("CPU fog reference", progress);
            c.reference = cpuFogReference(scene, request.camera, frame.width, frame.height, c.note);
            c.note = "compared: the fog (the scene has no surfaces) against the CPU fog "
                     "reference";
        }
    } else if (target.kind == Kind::PathTraced) {
        ProgressTicker ticker("path-traced reference", progress);
        c.reference = pathTracedReference(scene, pathTracedSettings(scene), request.camera,
                                          frame.width, frame.height, c.note)
                          .radiance;
    }
    if (c.compared.pixels.empty()) c.compared = frame.hdr;
    c.error = compareLinear(c.compared, c.reference);
    return c;
}

} // namespace veil::compare
