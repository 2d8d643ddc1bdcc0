#include "frame/renderer_setup.h"

#include "base/error.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace veil::frame {

std::unique_ptr<oit::Technique> createOitTechnique(const scene::Scene& scene,
                                                   const RendererOptions& options,
                                                   const gpu::ContextInfo& context,
                                                   gpu::ProgramManager& programs) {
    const std::string name = options.oit.empty() ? scene.render.oit : options.oit;
    const auto& registry = oit::Registry::instance();
    if (!options.oitProperties.is_null())
        return registry.create(name, context, programs, options.oitProperties, "OIT properties");
    if (name == scene.render.oit)
        return registry.create(name, context, programs, scene.render.oitProperties,
                               scene.render.oitWhere);
    return registry.create(name, context, programs, {}, "--oit"); // another: its defaults
}

std::unique_ptr<shadows::Technique> createShadowTechnique(const scene::Scene& scene,
                                                          const RendererOptions& options,
                                                          const gpu::ContextInfo& context,
                                                          gpu::ProgramManager& programs,
                                                          std::string& where) {
    const std::string name = options.shadows.empty() ? scene.render.shadows : options.shadows;
    const auto& registry = shadows::Registry::instance();
    if (!options.shadowProperties.is_null()) {
        where = "shadow properties";
        return registry.create(name, context, programs, options.shadowProperties, where);
    }
    if (name == scene.render.shadows) {
        where = scene.render.shadowsWhere;
        return registry.create(name, context, programs, scene.render.shadowProperties, where);
    }
    where = "--shadows"; // another technique than the scene's: its defaults
    return registry.create(name, context, programs, {}, where);
}

void checkFogWork(const scene::Scene& scene, const gpu::ContextInfo& context, int width,
                  int height) {
    if (scene.volumes.empty()) return;
    long long limit = scene.render.fogSampleLimit;
    if (limit < 0) limit = context.softwareRenderer ? 300'000'000LL : 0; // automatic
    if (limit == 0) return;
    const long long d = scene.render.fogResolution;
    const long long samples = ((width + d - 1) / d) * ((height + d - 1) / d) *
                              static_cast<long long>(scene.render.fogSteps);
    VEIL_CHECK(samples <= limit,
               "{}: fog: {}x{} pixels at 1/{} resolution x {} steps = {:.3g} samples, over the "
               "limit of {:.3g}{} (render.fog_sample_limit; lower render.fog_steps or the image "
               "size, raise render.fog_resolution, or set the limit)",
               scene.sourcePath.empty() ? std::string("<scene>") : scene.sourcePath.string(), width,
               height, d, scene.render.fogSteps, double(samples), double(limit),
               scene.render.fogSampleLimit < 0 ? " for a software renderer" : "");
}

void checkShadowWork(const scene::Scene& scene, const gpu::ContextInfo& context,
                     const shadows::Technique& technique, const std::string& where, int mapSize,
                     int viewCount) {
    long long limit = scene.render.fogSampleLimit;
    if (limit < 0) limit = context.softwareRenderer ? 300'000'000LL : 0; // automatic
    if (limit == 0) return;
    bool media = false;
    for (const scene::VolumeRef& v : scene.volumes)
        media = media || v.procedural != "homogeneous"; // grid volumes: files or procedural
    const shadows::Technique::WorkEstimate w = technique.work(mapSize, viewCount, media);
    VEIL_CHECK(w.samples <= double(limit),
               "{}: shadows {} ({}): {} = {:.3g} samples per frame, over the limit of {:.3g}{} "
               "(render.fog_sample_limit; lower those properties, or set the limit)",
               scene.sourcePath.empty() ? std::string("<scene>") : scene.sourcePath.string(),
               technique.name(), where, w.breakdown, w.samples, double(limit),
               scene.render.fogSampleLimit < 0 ? " for a software renderer" : "");
}

CameraBlock cameraBlock(const scene::Camera& camera, int width, int height) {
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    CameraBlock cam{};
    cam.view = camera.view();
    cam.projection = camera.projection(aspect);
    cam.viewProjection = cam.projection * cam.view;
    const glm::mat4 invView = glm::inverse(cam.view);
    cam.cameraPosition = glm::vec4(glm::vec3(invView[3]), 1.0f);
    cam.cameraRight = glm::vec4(glm::vec3(invView[0]), 0.0f);
    cam.cameraUp = glm::vec4(glm::vec3(invView[1]), 0.0f);
    cam.cameraForward = glm::vec4(-glm::vec3(invView[2]),
                                  camera.type == scene::CameraType::Orthographic ? 1.0f : 0.0f);
    cam.viewport = {width, height, camera.nearPlane, camera.farPlane};
    return cam;
}

LightsBlock lightsBlock(const scene::Scene& scene, const std::vector<int>& shadowedLights) {
    std::vector<bool> shadowed(VEIL_MAX_LIGHTS, false);
    for (int i : shadowedLights)
        shadowed[i] = true;
    LightsBlock block{};
    int count = 0;
    for (const auto& light : scene.lights) {
        if (count == VEIL_MAX_LIGHTS) break;
        LightEntry& e = block.lights[count];
        const int type = light.type == scene::LightType::Directional ? VEIL_LIGHT_DIRECTIONAL
                         : light.type == scene::LightType::Spot      ? VEIL_LIGHT_SPOT
                                                                     : VEIL_LIGHT_POINT;
        e.positionType = glm::vec4(light.position, static_cast<float>(type));
        e.directionShadow =
            glm::vec4(glm::normalize(light.direction), shadowed[count] ? 1.0f : 0.0f);
        e.radiance = glm::vec4(light.color * light.intensity, 0.0f);
        e.cone = glm::vec4(std::cos(glm::radians(light.innerConeDegrees)),
                           std::cos(glm::radians(light.outerConeDegrees)), 0.0f, 0.0f);
        ++count;
    }
    block.lightCount = glm::ivec4(count, 0, 0, 0);
    block.ambient = glm::vec4(scene.render.ambient, 0.0f);
    return block;
}

} // namespace veil::frame
