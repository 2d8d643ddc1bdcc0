#include "frame/renderer.h"

#include "base/error.h"
#include "base/log.h"
#include "frame/frame_uniforms.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <cmath>

namespace veil::frame {

namespace {
// Refuses a fog march whose work (marched pixels x steps) is past render.fog_sample_limit
// before any volume is loaded: on llvmpipe 2048^2 pixels x 4096 steps would take days.
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

gpu::GpuTimer::Mode timerModeFor(const gpu::ContextInfo& context) {
    // llvmpipe's timer queries read zero: time there with glFinish and the CPU clock.
    return (context.softwareRenderer || context.timerQueryBits == 0)
               ? gpu::GpuTimer::Mode::CpuFinish
               : gpu::GpuTimer::Mode::Query;
}
} // namespace

Renderer::Renderer(const scene::Scene& scene, const gpu::ContextInfo& context,
                   const RendererOptions& options)
    : scene_(scene), context_(context), timer_(timerModeFor(context)) {
    width_ = options.width > 0 ? options.width : scene.render.width;
    height_ = options.height > 0 ? options.height : scene.render.height;
    VEIL_CHECK(width_ > 0 && height_ > 0 && width_ <= 16384 && height_ <= 16384,
               "image size {}x{} out of range 1..16384", width_, height_);
    camera_ = scene.camera(options.camera.empty() ? scene.render.camera : options.camera);
    oitName_ = options.oit.empty() ? scene.render.oit : options.oit;
    if (!options.oitProperties.is_null())
        oit_ = oit::Registry::instance().create(oitName_, context_, programs_,
                                                options.oitProperties, "OIT properties");
    else if (oitName_ == scene.render.oit)
        oit_ = oit::Registry::instance().create(oitName_, context_, programs_,
                                                scene.render.oitProperties, scene.render.oitWhere);
    else // another technique than the scene's (--oit): its defaults
        oit_ = oit::Registry::instance().create(oitName_, context_, programs_, {}, "--oit");
    scene.bounds(boundsLo_, boundsHi_);

    using gpu::ProgramDesc;
    // Receivers (opaque and transparent surfaces, the fog) see lights through the shadow
    // technique's visibility include.
    const gpu::IncludeAliases visibility{
        {"veil:light_visibility", shadows::ShadowMap::visibilityInclude()}};
    opaqueProgram_ = programs_.add(
        ProgramDesc::graphics("frame/mesh.vert", "frame/opaque.frag", {}, visibility));
    shadowProgram_ = programs_.add(ProgramDesc::graphics("frame/mesh.vert", "frame/shadow.frag"));
    for (int pass = 0; pass < oit_->geometryPasses(); ++pass) {
        std::vector<std::string> defines = oit_->defines(pass);
        defines.push_back(fmt::format("OIT_PASS {}", pass));
        transparentPrograms_.push_back(programs_.add(
            ProgramDesc::graphics("frame/mesh.vert", "frame/transparent.frag", std::move(defines),
                                  {{"veil:oit_emit", oit_->emitInclude()}, visibility[0]})));
    }
    tonemapProgram_ = programs_.add(ProgramDesc::compute("frame/tonemap.comp"));

    checkFogWork(scene, context_, width_, height_);
    fog_ = std::make_unique<volume::FogPass>(scene, programs_, visibility);
    if (!fog_->active())
        fog_.reset();
    else
        for (int pass = 0; pass < oit_->geometryPasses(); ++pass) {
            std::vector<std::string> defines = oit_->defines(pass);
            defines.push_back(fmt::format("OIT_PASS {}", pass));
            fogEmitPrograms_.push_back(programs_.add(ProgramDesc::graphics(
                "volume/fullscreen.vert", "volume/fog_emit.frag", std::move(defines),
                {{"veil:oit_emit", oit_->emitInclude()}})));
        }

    meshes_.reserve(scene.meshes.size());
    for (const auto& mesh : scene.meshes)
        meshes_.emplace_back(mesh);

    for (std::size_t i = 0; i < scene.lights.size() && i < VEIL_MAX_LIGHTS; ++i) {
        const auto& light = scene.lights[i];
        if (light.castShadows && light.type != scene::LightType::Point) {
            shadowLight_ = static_cast<int>(i);
            break;
        }
    }
    if (scene.lights.size() > VEIL_MAX_LIGHTS)
        log::warn("scene has {} lights; only the first {} are used", scene.lights.size(),
                  VEIL_MAX_LIGHTS);
    if (shadowLight_ >= 0) shadowMap_.emplace(scene.render.shadowMapSize);

    cameraUbo_ = gpu::Buffer();
    cameraUbo_.setStorage(sizeof(CameraBlock), nullptr);
    lightsUbo_ = gpu::Buffer();
    lightsUbo_.setStorage(sizeof(LightsBlock), nullptr);
    createTargets();
    buildPasses();
}

Renderer::~Renderer() = default;

void Renderer::createTargets() {
    hdr_ = gpu::Texture(GL_TEXTURE_2D);
    hdr_.storage2D(1, GL_RGBA16F, width_, height_)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    depth_ = gpu::Texture(GL_TEXTURE_2D);
    depth_.storage2D(1, GL_DEPTH_COMPONENT32F, width_, height_)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    ldr_ = gpu::Texture(GL_TEXTURE_2D);
    ldr_.storage2D(1, GL_RGBA8, width_, height_);
    opaqueFbo_ = gpu::Framebuffer();
    opaqueFbo_.attach(GL_COLOR_ATTACHMENT0, hdr_)
        .attach(GL_DEPTH_ATTACHMENT, depth_)
        .drawBuffers({GL_COLOR_ATTACHMENT0});
    opaqueFbo_.checkComplete("opaque");
    targets_ = {width_, height_, &hdr_, &depth_, scene_.render.seed, &state_};
    oit_->resize(targets_);
}

void Renderer::updateUniforms() {
    const float aspect = static_cast<float>(width_) / static_cast<float>(height_);
    CameraBlock cam{};
    cam.view = camera_.view();
    cam.projection = camera_.projection(aspect);
    cam.viewProjection = cam.projection * cam.view;
    const glm::mat4 invView = glm::inverse(cam.view);
    cam.cameraPosition = glm::vec4(glm::vec3(invView[3]), 1.0f);
    cam.cameraRight = glm::vec4(glm::vec3(invView[0]), 0.0f);
    cam.cameraUp = glm::vec4(glm::vec3(invView[1]), 0.0f);
    cam.cameraForward = glm::vec4(-glm::vec3(invView[2]),
                                  camera_.type == scene::CameraType::Orthographic ? 1.0f : 0.0f);
    cam.viewport = {width_, height_, camera_.nearPlane, camera_.farPlane};
    cameraUbo_.setSubData(0, sizeof(cam), &cam);

    LightsBlock block{};
    int count = 0;
    for (const auto& light : scene_.lights) {
        if (count == VEIL_MAX_LIGHTS) break;
        LightEntry& e = block.lights[count];
        const int type = light.type == scene::LightType::Directional ? VEIL_LIGHT_DIRECTIONAL
                         : light.type == scene::LightType::Spot      ? VEIL_LIGHT_SPOT
                                                                     : VEIL_LIGHT_POINT;
        e.positionType = glm::vec4(light.position, static_cast<float>(type));
        e.directionShadow =
            glm::vec4(glm::normalize(light.direction), count == shadowLight_ ? 1.0f : 0.0f);
        e.radiance = glm::vec4(light.color * light.intensity, 0.0f);
        e.cone = glm::vec4(std::cos(glm::radians(light.innerConeDegrees)),
                           std::cos(glm::radians(light.outerConeDegrees)), 0.0f, 0.0f);
        ++count;
    }
    block.lightCount = glm::ivec4(count, 0, 0, 0);
    block.ambient = glm::vec4(scene_.render.ambient, 0.0f);
    if (shadowMap_) {
        block.shadowMatrix = shadowMap_->textureMatrix();
        block.shadowView = shadowMap_->view();
        block.shadowDepthRange = glm::vec4(shadowMap_->nearPlane(), shadowMap_->farPlane(), 0, 0);
        block.shadowParams =
            glm::vec4(scene_.render.shadowBias, static_cast<float>(scene_.render.pcfRadius),
                      1.0f / static_cast<float>(shadowMap_->size()), 1.0f);
    }
    lightsUbo_.setSubData(0, sizeof(block), &block);
}

void Renderer::drawObjects(const gpu::Program& program, Subset subset) const {
    program.use();
    for (const auto& object : scene_.objects) {
        const scene::Material& m = scene_.materials.at(object.material);
        const bool transparent = m.isTransparent();
        if (subset == Subset::Opaque && transparent) continue;
        if (subset == Subset::Transparent && !transparent) continue;
        if (subset == Subset::ShadowCasters && (transparent || !object.castShadows)) continue;
        const GpuMesh& mesh = meshes_.at(object.mesh);
        program.set("model", object.transform)
            .set("normalMatrix", glm::inverseTranspose(glm::mat3(object.transform)))
            .set("billboard", mesh.billboard() ? 1 : 0)
            .set("baseColor", m.baseColor)
            .set("roughness", m.roughness)
            .set("metalness", m.metalness)
            .set("emission", m.emission)
            .set("coverage", m.alpha)
            .set("transmission", m.transmission)
            .set("collimation", m.collimation)
            .set("ior", m.ior)
            .set("attenuationColor", m.attenuationColor)
            .set("attenuationDistance", m.attenuationDistance);
        mesh.draw();
    }
    glBindVertexArray(0);
}

void Renderer::render() {
    // Fit the shadow map first: updateUniforms() reads its matrix.
    if (shadowMap_) shadowMap_->fit(scene_.lights[shadowLight_], boundsLo_, boundsHi_);
    updateUniforms();
    // Whatever ran since the last frame (another renderer, a voxelization, the viewer's UI)
    // may have changed GL state: the first pass sets all of its declared state.
    state_.invalidate();
    cameraUbo_.bindBase(GL_UNIFORM_BUFFER, VEIL_UBO_CAMERA);
    lightsUbo_.bindBase(GL_UNIFORM_BUFFER, VEIL_UBO_LIGHTS);

    const float aspect = static_cast<float>(width_) / static_cast<float>(height_);
    fogTargets_ = {width_,
                   height_,
                   &depth_,
                   camera_.projection(aspect) * camera_.view(),
                   camera_.projection(aspect),
                   scene_.render.seed};
    for (const Pass& pass : passes_.passes()) {
        gpu::TimerScope t(timer_, pass.name);
        pass.execute();
    }
    passTimes_ = timer_.collect();
}

void Renderer::buildPasses() {
    // Resources of the light that owns the shadow map (one today; the shadows issue adds one
    // per shadow-casting light).
    std::vector<std::string> shadowResources;
    if (shadowMap_) shadowResources.push_back(fmt::format("shadow.{}", shadowLight_));
    auto plus = [](std::vector<std::string> a, const std::vector<std::string>& b) {
        a.insert(a.end(), b.begin(), b.end());
        return a;
    };

    if (shadowMap_)
        passes_.add(
            {"shadow", {}, shadowResources, [this] {
                 const gpu::Program& program = programs_.get(shadowProgram_);
                 program.set("useOverride", 1).set("viewProjection", shadowMap_->viewProjection());
                 shadowMap_->render(state_, [&] { drawObjects(program, Subset::ShadowCasters); });
                 shadowMap_->texture().bind(VEIL_TEX_SHADOW_MAP);
             }});

    passes_.add({"opaque", shadowResources, {"depth", "hdr"}, [this] {
                     opaqueFbo_.bind();
                     gpu::PipelineState state;
                     state.view(width_, height_).depth(GL_LESS, true);
                     state_.apply(state); // before the clears: they obey the colour/depth masks
                     const glm::vec4 bg(scene_.render.background, 1.0f);
                     const float one = 1.0f;
                     glClearNamedFramebufferfv(opaqueFbo_.id(), GL_COLOR, 0, &bg.x);
                     glClearNamedFramebufferfv(opaqueFbo_.id(), GL_DEPTH, 0, &one);
                     const gpu::Program& program = programs_.get(opaqueProgram_);
                     program.set("useOverride", 0);
                     drawObjects(program, Subset::Opaque);
                     glBindFramebuffer(GL_FRAMEBUFFER, 0);
                 }});

    std::vector<std::string> transparentReads = plus({"depth"}, shadowResources);
    if (fog_) {
        passes_.add({"fog",
                     plus({"depth"}, shadowResources),
                     {"fog.light_transmittance", "fog.radiance"},
                     [this] { fog_->march(fogTargets_); }});
        transparentReads.push_back("fog.radiance");
    }

    passes_.add({"transparent", transparentReads, {"oit.accumulation"}, [this] {
                     for (int pass = 0; pass < oit_->geometryPasses(); ++pass) {
                         const gpu::Program& program = programs_.get(transparentPrograms_[pass]);
                         program.set("useOverride", 0);
                         oit_->beginAccumulate(pass, targets_, program);
                         if (fog_) {
                             // Fog first: one contribution per pixel through the same oitEmit().
                             const gpu::Program& fogProgram = programs_.get(fogEmitPrograms_[pass]);
                             oit_->prepareProgram(pass, fogProgram);
                             fog_->bindForEmit(fogProgram, fogTargets_);
                             fogProgram.use();
                             fog_->drawEmit();
                         }
                         drawObjects(program, Subset::Transparent);
                         oit_->endAccumulate(pass);
                         if (pass + 1 == oit_->geometryPasses() && oit_->repeatAccumulation())
                             pass = -1;
                     }
                 }});

    passes_.add(
        {"resolve", {"oit.accumulation", "hdr"}, {"hdr"}, [this] { oit_->resolve(targets_); }});

    passes_.add({"tonemap", {"hdr"}, {"ldr"}, [this] {
                     const gpu::Program& program = programs_.get(tonemapProgram_);
                     program.use();
                     program.set("exposure", scene_.render.exposure)
                         .set("operatorId", scene_.render.tonemap == "clamp" ? 1 : 0);
                     hdr_.bind(VEIL_TEX_HDR);
                     glBindImageTexture(VEIL_IMG_OUTPUT, ldr_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                                        GL_RGBA8);
                     glDispatchCompute((width_ + 7) / 8, (height_ + 7) / 8, 1);
                     glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
                 }});
    passes_.validate();
}

const gpu::Texture* Renderer::resourceTexture(const std::string& name) const {
    if (name == "depth") return &depth_;
    if (name == "hdr") return &hdr_;
    if (name == "ldr") return &ldr_;
    if (shadowMap_ && name == fmt::format("shadow.{}", shadowLight_)) return &shadowMap_->texture();
    if (fog_ && name == "fog.radiance") return &fog_->radianceTexture();
    if (fog_ && name == "fog.light_transmittance") return fog_->lightTransmittanceTexture(0);
    return nullptr;
}

gpu::ImageF Renderer::readHdr() const { return gpu::readTexture(hdr_); }
gpu::ImageF Renderer::readLdr() const { return gpu::readTexture(ldr_); }

std::size_t Renderer::gpuBytes() const {
    std::size_t bytes = static_cast<std::size_t>(width_) * height_ * (8 + 4 + 4);
    for (const auto& m : meshes_)
        bytes += m.gpuBytes();
    if (shadowMap_) bytes += static_cast<std::size_t>(shadowMap_->size()) * shadowMap_->size() * 4;
    bytes += static_cast<std::size_t>(width_) * height_ * oit_->bytesPerPixel();
    if (fog_) bytes += fog_->gpuBytes();
    return bytes;
}

} // namespace veil::frame
