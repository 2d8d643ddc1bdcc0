#include "frame/frame_setup.h"

#include "base/error.h"
#include "frame/stages/opaque_stage.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <limits>

namespace veil::frame {

TechniqueChoice chooseTechnique(const std::string& option, const nlohmann::json& optionProperties,
                                const std::string& optionWhere, const std::string& sceneName,
                                const nlohmann::json& sceneProperties,
                                const std::string& sceneWhere, const std::string& flag) {
    const std::string name = option.empty() ? sceneName : option;
    if (!optionProperties.is_null()) return {name, optionProperties, optionWhere};
    if (name == sceneName) return {name, sceneProperties, sceneWhere};
    return {name, nlohmann::json{}, flag}; // another technique than the scene's: its defaults
}

TechniqueChoice oitChoice(const scene::Scene& scene, const RendererOptions& options) {
    return chooseTechnique(options.oit, options.oitProperties, "OIT properties", scene.render.oit,
                           scene.render.oitProperties, scene.render.oitWhere, "--oit");
}

TechniqueChoice shadowChoice(const scene::Scene& scene, const RendererOptions& options) {
    return chooseTechnique(options.shadows, options.shadowProperties, "shadow properties",
                           scene.render.shadows, scene.render.shadowProperties,
                           scene.render.shadowsWhere, "--shadows");
}

FrameStages buildStages(const scene::Scene& scene, const gpu::ContextInfo& context,
                        const RendererOptions& options, gpu::ProgramManager& programs, int width,
                        int height, int slabTexels) {
    // The OIT technique first (an unknown or unavailable one is refused before any volume
    // loads); its programs become the transparency stage's.
    const TechniqueChoice oit = oitChoice(scene, options);
    const std::size_t oitMark = programs.size();
    std::unique_ptr<oit::Technique> technique =
        oit::Registry::instance().create(oit.name, context, programs, oit.properties, oit.where);
    std::vector<gpu::ProgramHandle> techniquePrograms = programs.handlesFrom(oitMark);

    const TechniqueChoice sc = shadowChoice(scene, options);
    auto shadows = std::make_unique<ShadowStage>(
        scene, context, programs,
        shadows::Registry::instance().create(sc.name, context, programs, sc.properties, sc.where),
        sc.where);
    const auto receivers = shadows->technique().receivers(); // visibility include, defines
    const std::filesystem::path& visibility = receivers.visibility;

    const Properties aoProperties = AmbientOcclusion::schema().resolve(
        scene.render.aoProperties, scene.render.aoWhere, "the AO pass");
    std::unique_ptr<AmbientOcclusion> ao;
    if (aoProperties.getBool("enabled"))
        ao = std::make_unique<AmbientOcclusion>(programs, aoProperties);
    auto tonemap = std::make_unique<TonemapStage>(programs);

    checkFogWork(scene, context, width, height);
    auto fogPass = std::make_unique<volume::FogPass>(
        scene, programs, gpu::IncludeAliases{{"veil:light_visibility", visibility}});
    // With AO the opaque shading reads the AO buffer (define VEIL_AO); with a scattered-light
    // cache surfaces receive its light (VEIL_SURFACE_SCATTERED_LIGHT, bound by the fog stage);
    // without either, the program is the one it always was. The shadow technique's receiver
    // defines follow.
    std::vector<std::string> opaqueDefines;
    if (ao) opaqueDefines.push_back("VEIL_AO 1");
    if (fogPass->scatteredLightCache()) opaqueDefines.push_back(kSurfaceScatteredLightDefine);
    opaqueDefines.insert(opaqueDefines.end(), receivers.defines.begin(), receivers.defines.end());
    const gpu::ProgramHandle opaqueProgram = programs.add(
        gpu::ProgramDesc::graphics("frame/mesh.vert", "frame/opaque.frag", std::move(opaqueDefines),
                                   {{"veil:light_visibility", visibility}}));
    glm::vec3 lo, hi;
    scene.bounds(lo, hi);
    std::unique_ptr<FogStage> fog;
    if (fogPass->active()) {
        // A technique whose maps hold the volumes' absorbance replaces the fog's own
        // self-shadowing volumes (one answer for every receiver, counted once).
        fogPass->setSelfShadowing(!(shadows->technique().attenuatesMedia() && shadows->casting()));
        // The light views hold the volumes too: they cast (into maps that replace the
        // marcher's self-shadowing) and receive (every fog sample asks the maps).
        if (scene.objects.empty()) {
            lo = glm::vec3(std::numeric_limits<float>::max());
            hi = glm::vec3(std::numeric_limits<float>::lowest());
        }
        fogPass->extendBounds(lo, hi);
        if (lo.x > hi.x) lo = hi = glm::vec3(0.0f); // global fog only
        if (fogPass->hasGridVolumes() && shadows->casting())
            shadows->technique().checkReceiverWork(
                context, scene.render.fogSteps, static_cast<int>(shadows->lights().lights.size()),
                sc.where);
        fog = std::make_unique<FogStage>(std::move(fogPass), slabTexels);
    }
    shadows->setBounds(lo, hi);

    std::unique_ptr<TransparencyStage> transparency =
        TransparencyStage::create(std::move(technique), std::move(techniquePrograms), scene,
                                  programs, fog ? &fog->fog() : nullptr, receivers);
    FrameStages s;
    s.transparency = transparency.get();
    s.shadows = shadows.get();
    s.list.push_back(std::move(shadows));
    if (ao) {
        s.ao = ao.get();
        s.list.push_back(std::make_unique<OpaqueStage>(programs, opaqueProgram,
                                                       OpaqueStage::Mode::DepthPrepass));
        s.list.push_back(std::move(ao));
    }
    s.list.push_back(std::make_unique<OpaqueStage>(programs, opaqueProgram,
                                                   s.ao ? OpaqueStage::Mode::ShadedAfterPrepass
                                                        : OpaqueStage::Mode::Shaded));
    if (fog) {
        s.fog = fog.get();
        s.list.push_back(std::move(fog));
    }
    s.list.push_back(std::move(transparency));
    s.list.push_back(std::move(tonemap));
    return s;
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
