// One headless frame of a scene, rendered with frame::Renderer and read back with everything
// `veil render` writes and reports about it: linear HDR and tone-mapped images, per-pass
// times, the techniques' effective properties and statistics, Z, AOVs and camera matrices.
// `veil render`, `veil regress` and the Python module (python/) render through this.
#pragma once

#include "base/image.h"
#include "capture/exr_output.h"
#include "gpu/context.h"
#include "gpu/timer.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace veil::capture {

struct FrameRequest {
    int width = 0, height = 0; // 0: the scene's render.width / render.height
    std::string camera;        // empty: the scene's render.camera
    std::string oit;           // empty: the scene's render.oit
    std::string shadows;       // empty: the scene's render.shadows
    // The shadow technique's properties (null: the scene's when it is the scene's technique).
    nlohmann::json shadowProperties;
    bool fogAov = false;           // read fog.R/G/B and fog.transmittance (needs fog)
    std::filesystem::path dumpDir; // not empty: every frame resource into it (capture/dump.h)
    // Not null: the linear HDR image goes into these hdrOutCount floats (RGBA, top row first;
    // the frame's width * height * 4) instead of RenderedFrame::hdr, which stays empty.
    float* hdrOut = nullptr;
    std::size_t hdrOutCount = 0;
};

struct RenderedFrame {
    std::string oit;
    ImageF hdr, ldr; // RGBA float, top row first: linear radiance, tone-mapped sRGB
    nlohmann::json passes = nlohmann::json::array(); // [{name, ms}] of the frame
    double totalMs = 0.0;
    std::size_t gpuBytes = 0;
    int width = 0, height = 0;
    std::string camera;
    gpu::GpuTimer::Mode timer = gpu::GpuTimer::Mode::CpuFinish;
    nlohmann::json oitStats;      // technique-specific counters (reference: fragments, pool)
    nlohmann::json oitProperties; // effective values of the technique's properties
    std::string shadows;
    nlohmann::json shadowStats, shadowProperties;          // the same for the shadow technique
    nlohmann::json shadowLights = nlohmann::json::array(); // scene light indices with maps
    nlohmann::json framePasses = nlohmann::json::array();  // the frame's passes and resources
    nlohmann::json volumes = nlohmann::json::array();
    double scatteredLightBakeMs = -1.0; // the fog's scattered-light cache bake (-1: none)
    FrameExtras extras;                 // Z, AOVs and camera matrices (capture/exr_output.h)
    nlohmann::json dumpManifest;        // FrameRequest::dumpDir
};

// Renders one frame in the current context (a new frame::Renderer, as `veil render` does) and
// reads it back. Throws veil::Error (unknown technique or camera, no fog for the fog AOV, ...).
RenderedFrame renderFrame(const scene::Scene& scene, const gpu::ContextInfo& info,
                          const FrameRequest& request);

// The frame's part of `veil render --report`: gpu_bytes, passes, total_ms, oit_stats (when
// any), oit_properties, frame_passes, shadows, shadow_properties, shadow_lights,
// shadow_stats (when any), volumes (when any), scattered_light_bake_ms (with the fog's
// scattered-light cache: its last bake, run before the timed passes), timer.
nlohmann::json frameReport(const RenderedFrame& frame);

} // namespace veil::capture
