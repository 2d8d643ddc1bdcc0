#include "capture/frame_capture.h"

#include "capture/dump.h"
#include "fog/fog_pass.h"
#include "frame/renderer.h"
#include "oit/technique.h"
#include "shadows/technique.h"

#include <optional>

namespace veil::capture {

RenderedFrame renderFrame(const scene::Scene& scene, const gpu::ContextInfo& info,
                          const FrameRequest& request) {
    const bool dump = !request.dumpDir.empty();
    frame::Renderer renderer(scene, info,
                             frame::RendererOptions{request.width,
                                                    request.height,
                                                    request.camera,
                                                    request.oit,
                                                    {},
                                                    request.shadows,
                                                    request.shadowProperties});
    // Readers of the fog's per-pixel march (skipped under piecewise fog otherwise).
    renderer.keepFogRadiance(request.fogAov || dump);
    renderer.render();
    RenderedFrame r;
    r.oit = renderer.oitName();
    if (request.hdrOut)
        renderer.readHdrInto(request.hdrOut, request.hdrOutCount);
    else
        r.hdr = renderer.readHdr();
    r.ldr = renderer.readLdr();
    for (const auto& p : renderer.passTimes()) {
        r.passes.push_back({{"name", p.name}, {"ms", p.milliseconds}});
        r.totalMs += p.milliseconds;
    }
    r.gpuBytes = renderer.gpuBytes();
    if (const volume::FogPass* fog = renderer.fog()) {
        r.scatteredLightBakeMs = fog->scatteredLightBakeMs();
        for (const auto& v : fog->stats())
            r.volumes.push_back({{"gpu_bytes", v.gpuBytes},
                                 {"grid_bytes", v.gridBytes},
                                 {"active_voxels", v.activeVoxels},
                                 {"layout", v.dense ? "dense" : "brick atlas"},
                                 {"bricks", v.bricks},
                                 {"coarsened", v.coarsened}});
    }
    r.width = renderer.width();
    r.height = renderer.height();
    r.camera = renderer.camera().name;
    r.timer = renderer.timerMode();
    if (nlohmann::json stats = renderer.technique().stats(); !stats.empty())
        r.oitStats = std::move(stats);
    r.oitProperties = renderer.technique().properties().values();
    r.shadows = renderer.shadowTechnique().name();
    if (nlohmann::json stats = renderer.shadowTechnique().stats(); !stats.empty())
        r.shadowStats = std::move(stats);
    r.shadowProperties = renderer.shadowTechnique().properties().values();
    r.shadowLights = renderer.shadowLights().lights;
    for (const frame::Pass& p : renderer.passes().passes())
        r.framePasses.push_back({{"name", p.name}, {"reads", p.reads}, {"writes", p.writes}});
    r.extras = captureExtras(renderer, request.fogAov);
    if (dump) r.dumpManifest = dumpFrame(renderer, request.dumpDir);
    return r;
}

nlohmann::json frameReport(const RenderedFrame& f) {
    nlohmann::json report;
    report["gpu_bytes"] = f.gpuBytes;
    report["passes"] = f.passes;
    report["total_ms"] = f.totalMs;
    if (!f.oitStats.is_null()) report["oit_stats"] = f.oitStats;
    report["oit_properties"] = f.oitProperties;
    report["frame_passes"] = f.framePasses;
    report["shadows"] = f.shadows;
    report["shadow_properties"] = f.shadowProperties;
    report["shadow_lights"] = f.shadowLights;
    if (!f.shadowStats.is_null()) report["shadow_stats"] = f.shadowStats;
    if (!f.volumes.empty()) report["volumes"] = f.volumes;
    // Baked before the frame's passes, so not in `passes` or total_ms.
    if (f.scatteredLightBakeMs >= 0.0) report["scattered_light_bake_ms"] = f.scatteredLightBakeMs;
    report["timer"] = f.timer == gpu::GpuTimer::Mode::Query
                          ? "GL_TIME_ELAPSED"
                          : "glFinish + CPU clock (driver timer unusable)";
    return report;
}

} // namespace veil::capture
