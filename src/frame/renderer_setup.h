// What a frame::Renderer is built from: its options, the techniques they choose, the checks
// made before anything is loaded, and the uniform blocks every frame fills.
#pragma once

#include "frame/frame_uniforms.h"
#include "gpu/context.h"
#include "gpu/shader.h"
#include "oit/technique.h"
#include "scene/scene.h"
#include "shadows/technique.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace veil::frame {

struct RendererOptions {
    RendererOptions(int width_ = 0, int height_ = 0, std::string camera_ = {},
                    std::string oit_ = {}, nlohmann::json oitProperties_ = {},
                    std::string shadows_ = {}, nlohmann::json shadowProperties_ = {})
        : width(width_), height(height_), camera(std::move(camera_)), oit(std::move(oit_)),
          oitProperties(std::move(oitProperties_)), shadows(std::move(shadows_)),
          shadowProperties(std::move(shadowProperties_)) {}
    int width = 0;      // 0 = the scene's render.width
    int height = 0;     // 0 = the scene's render.height
    std::string camera; // empty = the scene's render.camera
    std::string oit;    // empty = the scene's render.oit
    // The technique's properties (a JSON object, see `veil techniques`). Null = the scene's
    // render.oit properties when the technique is the scene's, else the defaults.
    nlohmann::json oitProperties;
    std::string shadows; // empty = the scene's render.shadows
    // As oitProperties, for the shadow technique (null = the scene's when it is the scene's).
    nlohmann::json shadowProperties;
    // Keep the shadow technique's maps from the last frame while nothing they depend on
    // changed (Renderer::setReuseShadowMaps). Off for one-shot frames (`veil render`,
    // veil-bench: every frame draws its maps, so pass times stay honest); the viewer turns it
    // on (view.reuse_shadow_maps).
    bool reuseShadowMaps = false;
};

// The OIT technique of `options` (or the scene's render.oit) with its properties: the
// options' when given, the scene's when it is the scene's technique, else the defaults.
std::unique_ptr<oit::Technique> createOitTechnique(const scene::Scene& scene,
                                                   const RendererOptions& options,
                                                   const gpu::ContextInfo& context,
                                                   gpu::ProgramManager& programs);
// The same for the shadow technique; `where` receives where its properties came from (for
// errors naming the max_lights limit).
std::unique_ptr<shadows::Technique> createShadowTechnique(const scene::Scene& scene,
                                                          const RendererOptions& options,
                                                          const gpu::ContextInfo& context,
                                                          gpu::ProgramManager& programs,
                                                          std::string& where);

// Refuses a fog march whose work (marched pixels x steps) is past render.fog_sample_limit
// before any volume is loaded: on llvmpipe 2048^2 pixels x 4096 steps would take days.
void checkFogWork(const scene::Scene& scene, const gpu::ContextInfo& context, int width,
                  int height);
// The same limit for the shadow technique's own passes (shadows::Technique::work), checked
// before resize(mapSize, viewCount) allocates its maps: "where" names its properties.
void checkShadowWork(const scene::Scene& scene, const gpu::ContextInfo& context,
                     const shadows::Technique& technique, const std::string& where, int mapSize,
                     int viewCount);

// The camera block of `camera` for a width x height image.
CameraBlock cameraBlock(const scene::Camera& camera, int width, int height);
// The lights block of the scene's first VEIL_MAX_LIGHTS lights; `shadowed`: scene indices of
// the lights that cast shadows.
LightsBlock lightsBlock(const scene::Scene& scene, const std::vector<int>& shadowed);

} // namespace veil::frame
