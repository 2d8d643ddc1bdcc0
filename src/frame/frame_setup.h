// What a frame::Renderer is built from: its options, the techniques they choose, its stages in
// frame order, the checks made before anything is loaded, and the uniform blocks every frame
// fills.
#pragma once

#include "frame/frame_uniforms.h"
#include "frame/stages/ambient_occlusion.h"
#include "frame/stages/fog_stage.h"
#include "frame/stages/shadow_stage.h"
#include "frame/stages/transparency_stage.h"
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

// Which technique of a registry a renderer uses, and its properties: the option's technique
// (empty: the scene's) with the option's properties when given, the scene's when it is the
// scene's technique, else its defaults. One rule for the OIT and the shadow technique.
struct TechniqueChoice {
    std::string name;
    nlohmann::json properties;
    std::string where; // where the properties came from (messages)
};
TechniqueChoice chooseTechnique(const std::string& option, const nlohmann::json& optionProperties,
                                const std::string& optionWhere, const std::string& sceneName,
                                const nlohmann::json& sceneProperties,
                                const std::string& sceneWhere, const std::string& flag);
TechniqueChoice oitChoice(const scene::Scene& scene, const RendererOptions& options);
TechniqueChoice shadowChoice(const scene::Scene& scene, const RendererOptions& options);

// A renderer's stages in frame order: shadows, the depth pre-pass and AO (render.ao), opaque,
// fog (only with density volumes), transparency, tonemap; and the ones the frame talks to.
struct FrameStages {
    std::vector<std::unique_ptr<pass::Stage>> list;
    ShadowStage* shadows = nullptr;
    AmbientOcclusion* ao = nullptr;
    FogStage* fog = nullptr;
    TransparencyStage* transparency = nullptr;
};
// Builds them for a width x height frame (throws veil::Error naming what is wrong: technique,
// property, budget, volume file). `slabTexels`: the fog's refinement step.
FrameStages buildStages(const scene::Scene& scene, const gpu::ContextInfo& context,
                        const RendererOptions& options, gpu::ProgramManager& programs, int width,
                        int height, int slabTexels);

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
