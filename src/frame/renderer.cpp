#include "frame/renderer.h"

#include "base/error.h"
#include "base/log.h"
#include "frame/frame_uniforms.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <cmath>

// The OIT targets of the fog's compute emission (three at most) must fit the 8 image units
// that GL 4.5 guarantees (NVIDIA has exactly 8).
static_assert(VEIL_IMG_OIT_TARGET0 + 2 < 8, "OIT per-pixel emission images beyond unit 7");

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
    : scene_(scene), context_(context), reuseShadowMaps_(options.reuseShadowMaps),
      timer_(timerModeFor(context)) {
    width_ = options.width > 0 ? options.width : scene.render.width;
    height_ = options.height > 0 ? options.height : scene.render.height;
    VEIL_CHECK(width_ > 0 && height_ > 0 && width_ <= 16384 && height_ <= 16384,
               "image size {}x{} out of range 1..16384", width_, height_);
    camera_ = scene.camera(options.camera.empty() ? scene.render.camera : options.camera);
    oitName_ = options.oit.empty() ? scene.render.oit : options.oit;
    const std::size_t oitMark = programs_.size();
    if (!options.oitProperties.is_null())
        oit_ = oit::Registry::instance().create(oitName_, context_, programs_,
                                                options.oitProperties, "OIT properties");
    else if (oitName_ == scene.render.oit)
        oit_ = oit::Registry::instance().create(oitName_, context_, programs_,
                                                scene.render.oitProperties, scene.render.oitWhere);
    else // another technique than the scene's (--oit): its defaults
        oit_ = oit::Registry::instance().create(oitName_, context_, programs_, {}, "--oit");
    oitPrograms_ = programs_.handlesFrom(oitMark); // the technique's own (resolve, ...)
    scene.bounds(boundsLo_, boundsHi_);

    // The shadow technique, chosen like the OIT technique (render.shadows, --shadows).
    const std::string shadowsName =
        options.shadows.empty() ? scene.render.shadows : options.shadows;
    auto& shadowRegistry = shadows::Registry::instance();
    std::string shadowsWhere = scene.render.shadowsWhere;
    if (!options.shadowProperties.is_null()) {
        shadowsWhere = "shadow properties";
        shadows_ = shadowRegistry.create(shadowsName, context_, programs_, options.shadowProperties,
                                         shadowsWhere);
    } else if (shadowsName == scene.render.shadows) {
        shadows_ = shadowRegistry.create(shadowsName, context_, programs_,
                                         scene.render.shadowProperties, shadowsWhere);
    } else { // another technique than the scene's (--shadows): its defaults
        shadowsWhere = "--shadows";
        shadows_ = shadowRegistry.create(shadowsName, context_, programs_, {}, shadowsWhere);
    }
    const Properties& sp = shadows_->properties();
    shadowSet_ = shadows::chooseShadowLights(scene, sp.getInt("max_lights"),
                                             fmt::format("{} (max_lights)", shadowsWhere));
    if (shadowSet_.viewCount > 0) shadows_->resize(sp.getInt("size"), shadowSet_.viewCount);

    using gpu::ProgramDesc;
    // Receivers (opaque and transparent surfaces, the fog) see lights through the shadow
    // technique's visibility include.
    const gpu::IncludeAliases visibility{{"veil:light_visibility", shadows_->visibilityInclude()}};
    aoProperties_ = AmbientOcclusion::schema().resolve(scene.render.aoProperties,
                                                       scene.render.aoWhere, "the AO pass");
    if (aoProperties_.getBool("enabled"))
        ao_ = std::make_unique<AmbientOcclusion>(programs_, aoProperties_);
    // With AO the opaque shading reads the AO buffer (define VEIL_AO); without, the program is
    // the one it always was.
    opaqueProgram_ = programs_.add(ProgramDesc::graphics(
        "frame/mesh.vert", "frame/opaque.frag",
        ao_ ? std::vector<std::string>{"VEIL_AO 1"} : std::vector<std::string>{}, visibility));
    tonemapProgram_ = programs_.add(ProgramDesc::compute("frame/tonemap.comp"));

    checkFogWork(scene, context_, width_, height_);
    fog_ = std::make_unique<volume::FogPass>(scene, programs_, visibility);
    if (!fog_->active())
        fog_.reset();
    else {
        // A technique whose maps hold the volumes' absorbance replaces the fog's own
        // self-shadowing volumes (one answer for every receiver, counted once).
        fog_->setSelfShadowing(!(shadows_->attenuatesMedia() && shadowSet_.viewCount > 0));
    }
    const std::size_t passMark = programs_.size();
    addTechniquePrograms();
    for (gpu::ProgramHandle h : programs_.handlesFrom(passMark))
        oitPrograms_.push_back(h);

    meshes_.reserve(scene.meshes.size());
    for (const auto& mesh : scene.meshes)
        meshes_.emplace_back(mesh);

    if (scene.lights.size() > VEIL_MAX_LIGHTS)
        log::warn("scene has {} lights; only the first {} are used", scene.lights.size(),
                  VEIL_MAX_LIGHTS);

    shadowFrame_.mapSize = sp.getInt("size");
    shadowFrame_.state = &state_;
    shadowFrame_.views = &shadowViews_;
    shadowFrame_.scene = &scene_;
    shadowFrame_.seed = scene.render.seed;
    shadowFrame_.width = width_;
    shadowFrame_.height = height_;
    shadowFrame_.drawCasters = [this](const gpu::Program& program, shadows::CasterSet set) {
        drawObjects(program, set == shadows::CasterSet::Opaque ? Subset::OpaqueCasters
                                                               : Subset::TransparentCasters);
    };
    if (fog_ && fog_->hasGridVolumes())
        shadowFrame_.bindMedia = [this](const gpu::Program& program) {
            fog_->bindVolumes(program);
        };

    cameraUbo_ = gpu::Buffer();
    cameraUbo_.setStorage(sizeof(CameraBlock), nullptr);
    lightsUbo_ = gpu::Buffer();
    lightsUbo_.setStorage(sizeof(LightsBlock), nullptr);
    shadowsUbo_ = gpu::Buffer();
    shadowsUbo_.setStorage(sizeof(shadows::ShadowsBlock), nullptr);
    createTargets();
    buildPasses();
}

Renderer::~Renderer() = default;

// The fog between the OIT technique's sorted surfaces, piecewise (fog_segments.comp), for a
// technique with fogSegments() (`reference`); off for the others.
void Renderer::configureFogSegments() {
    if (!fog_) return;
    if (!oit_->fogSegments()) {
        fog_->disableSegments();
        return;
    }
    const int last = oit_->geometryPasses() - 1;
    std::vector<std::string> defines = oit_->defines(last);
    defines.push_back(fmt::format("OIT_PASS {}", last));
    fog_->enableSegments(std::move(defines), oit_->emitInclude());
}

// The OIT technique's programs: one transparent-surface and (with fog) one fog-emission
// program per geometry pass, each with the technique's emit include.
void Renderer::addTechniquePrograms() {
    using gpu::ProgramDesc;
    configureFogSegments();
    const gpu::IncludeAliases visibility{{"veil:light_visibility", shadows_->visibilityInclude()}};
    std::vector<gpu::ProgramHandle> transparent, fogEmit;
    for (int pass = 0; pass < oit_->geometryPasses(); ++pass) {
        std::vector<std::string> defines = oit_->defines(pass);
        defines.push_back(fmt::format("OIT_PASS {}", pass));
        transparent.push_back(programs_.add(
            ProgramDesc::graphics("frame/mesh.vert", "frame/transparent.frag", defines,
                                  {{"veil:oit_emit", oit_->emitInclude()}, visibility[0]})));
        if (!fog_) continue;
        // The fog's one contribution per pixel: from compute where the technique's emit file
        // writes its targets as images (oit::PerPixelEmit, issue 14), else as a full-screen
        // fragment; both through the technique's one oitEmit(). A technique with
        // fogSegments() gets the fog piecewise instead (configureFogSegments()).
        const oit::PerPixelEmit mode =
            fog_->segmented() ? oit::PerPixelEmit::None : oit_->perPixelEmit(pass);
        const gpu::IncludeAliases emit{{"veil:oit_emit", oit_->emitInclude()}};
        if (mode == oit::PerPixelEmit::Compute) {
            std::vector<std::string> computeDefines = defines;
            computeDefines.insert(computeDefines.begin(),
                                  "OIT_COMPUTE 1"); // before the technique's
            fogEmit.push_back(programs_.add(
                ProgramDesc::compute("volume/fog_emit.comp", std::move(computeDefines), emit)));
        } else if (mode == oit::PerPixelEmit::Fragments) {
            fogEmit.push_back(programs_.add(ProgramDesc::graphics(
                "volume/fullscreen.vert", "volume/fog_emit.frag", defines, emit)));
        } else {
            fogEmit.emplace_back();
        }
    }
    transparentPrograms_ = std::move(transparent);
    fogEmitPrograms_ = std::move(fogEmit);
}

void Renderer::setOitTechnique(const std::string& name, const nlohmann::json& properties,
                               const std::string& where) {
    // Built aside first: a failure leaves the current technique and programs in place. Every
    // program added from `mark` on is the new technique's (its own, its transparent and fog
    // programs); the old technique's are released once the new one stands.
    const std::size_t mark = programs_.size();
    std::unique_ptr<oit::Technique> next;
    const std::string previousName = oitName_;
    const std::vector<gpu::ProgramHandle> transparent = transparentPrograms_,
                                          fogEmit = fogEmitPrograms_;
    const volume::FogPass::SegmentsState segments =
        fog_ ? fog_->segmentsState() : volume::FogPass::SegmentsState{};
    try {
        next = oit::Registry::instance().create(name, context_, programs_, properties, where);
        std::swap(oit_, next);
        oitName_ = name;
        addTechniquePrograms();
        oit_->resize(targets_);
        rebuildPasses(); // the technique's targets are frame resources
    } catch (...) {
        for (gpu::ProgramHandle h : programs_.handlesFrom(mark))
            programs_.release(h);
        if (next) std::swap(oit_, next); // the previous technique back
        oitName_ = previousName;
        transparentPrograms_ = transparent;
        fogEmitPrograms_ = fogEmit;
        if (fog_) fog_->restoreSegments(segments); // the previous technique's, still built
        rebuildPasses();
        throw;
    }
    for (gpu::ProgramHandle h : oitPrograms_)
        programs_.release(h);
    oitPrograms_ = programs_.handlesFrom(mark);
}

void Renderer::rebuildPasses() {
    refine_.active = false; // another pass list: a refinement in progress starts again
    passes_ = PassList();
    buildPasses();
}

void Renderer::resize(int width, int height) {
    VEIL_CHECK(width > 0 && height > 0 && width <= 16384 && height <= 16384,
               "image size {}x{} out of range 1..16384", width, height);
    if (width == width_ && height == height_) return;
    checkFogWork(scene_, context_, width, height);
    refine_.active = false;
    width_ = width;
    height_ = height;
    shadowFrame_.width = width_; // screen-space shadow techniques
    shadowFrame_.height = height_;
    createTargets(); // the OIT technique's targets too; the fog resizes in march()
}

void Renderer::sceneValuesChanged() {
    if (fog_) fog_->invalidateLightVolumes();
    shadowMapsValid_ = false; // the lights' views and the media of the shadow maps
}

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
    if (ao_) {
        ao_->resize(width_, height_);
        targets_.ambientOcclusion = &ao_->visibility();
    }
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

    std::vector<bool> shadowed(VEIL_MAX_LIGHTS, false);
    for (int i : shadowSet_.lights)
        shadowed[i] = true;
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
            glm::vec4(glm::normalize(light.direction), shadowed[count] ? 1.0f : 0.0f);
        e.radiance = glm::vec4(light.color * light.intensity, 0.0f);
        e.cone = glm::vec4(std::cos(glm::radians(light.innerConeDegrees)),
                           std::cos(glm::radians(light.outerConeDegrees)), 0.0f, 0.0f);
        ++count;
    }
    block.lightCount = glm::ivec4(count, 0, 0, 0);
    block.ambient = glm::vec4(scene_.render.ambient, 0.0f);
    lightsUbo_.setSubData(0, sizeof(block), &block);

    // The shadowed lights' views, refitted every frame (lights and objects may move).
    shadowViews_ = shadows::fitViews(scene_, shadowSet_, boundsLo_, boundsHi_);
    shadows::ShadowsBlock sb{};
    shadows::fillShadowsBlock(sb, shadowViews_, shadowSet_, shadowFrame_.mapSize);
    shadows_->fillParams(sb);
    shadowsUbo_.setSubData(0, sizeof(sb), &sb);
}

void Renderer::drawObjects(const gpu::Program& program, Subset subset) const {
    program.use();
    for (const auto& object : scene_.objects) {
        const scene::Material& m = scene_.materials.at(object.material);
        const bool transparent = m.isTransparent();
        // A binary-coverage material's alpha = 1 interior is opaque (001 section 6).
        const bool binary = m.baseCoverageIsBinary();
        if (subset == Subset::Opaque && transparent && !binary) continue;
        if (subset == Subset::Transparent && !transparent) continue;
        if (subset == Subset::OpaqueCasters && (transparent || !object.castShadows)) continue;
        if (subset == Subset::TransparentCasters && (!transparent || !object.castShadows)) continue;
        const GpuMesh& mesh = meshes_.at(object.mesh);
        program.set("model", object.transform)
            .set("normalMatrix", glm::inverseTranspose(glm::mat3(object.transform)))
            .set("billboard", mesh.billboard() ? 1 : 0)
            .set("baseColor", m.baseColor)
            .set("roughness", m.roughness)
            .set("metalness", m.metalness)
            .set("emission", m.emission)
            .set("coverage", m.alpha)
            .set("coverageEdge", m.coverageEdge)
            .set("binaryCoverage", binary ? 1 : 0)
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
    beginFrame();
    runPasses(0, passes_.passes().size());
    passTimes_ = timer_.collect();
}

void Renderer::bindFrameState() {
    // Whatever ran since the last frame (another renderer, a voxelization, the viewer's UI)
    // may have changed GL state: the first pass sets all of its declared state.
    state_.invalidate();
    cameraUbo_.bindBase(GL_UNIFORM_BUFFER, VEIL_UBO_CAMERA);
    lightsUbo_.bindBase(GL_UNIFORM_BUFFER, VEIL_UBO_LIGHTS);
    shadowsUbo_.bindBase(GL_UNIFORM_BUFFER, VEIL_UBO_SHADOWS);
}

void Renderer::beginFrame() {
    updateUniforms();
    bindFrameState();

    const float aspect = static_cast<float>(width_) / static_cast<float>(height_);
    fogTargets_ = {};
    fogTargets_.width = width_;
    fogTargets_.height = height_;
    fogTargets_.depth = &depth_;
    fogTargets_.viewProjection = camera_.projection(aspect) * camera_.view();
    fogTargets_.projection = camera_.projection(aspect);
    fogTargets_.seed = scene_.render.seed;
    shadowFrame_.cameraViewProjection = fogTargets_.viewProjection;
    shadowFrame_.orthographicCamera = camera_.type == scene::CameraType::Orthographic;
    if (shadowSet_.viewCount > 0)
        fogTargets_.prepareReceiver = [this](const gpu::Program& program) {
            shadows_->prepareReceiver(program, shadowFrame_);
        };
    region_ = glm::ivec4(0, 0, width_, height_);
    skipShadowPasses_ = reuseShadowMaps_ && shadowMapsValid_ && shadowPassCount_ > 0 &&
                        !shadows_->dependsOnCamera();
}

void Renderer::setOitRegion() {
    targets_.region = region_;
    // Part of the frame (a refinement tile): hdr holds the opaque image inside region_ only.
    const bool part = region_ != glm::ivec4(0, 0, width_, height_);
    targets_.opaqueColor = part ? &opaqueHdr_ : nullptr;
}

void Renderer::runPasses(std::size_t first, std::size_t end) {
    const std::vector<Pass>& passes = passes_.passes();
    const bool shadowsHere = first < shadowPassCount_;
    if (shadowsHere && skipShadowPasses_) {
        first = shadowPassCount_; // the maps of an earlier frame stand
        ++shadowMapReuses_;
    } else if (shadowsHere) {
        shadowMapsValid_ = false; // until every shadow pass ran (one may throw)
    }
    for (std::size_t i = first; i < end; ++i) {
        gpu::TimerScope t(timer_, passes[i].name);
        passes[i].execute();
        if (i + 1 == shadowPassCount_) {
            shadowMapsValid_ = true;
            ++shadowMapRenders_;
        }
    }
}

void Renderer::buildPasses() {
    // The shadow technique's passes, when a light casts shadows; receivers read what its
    // visibility include samples and bind it before they draw.
    std::vector<std::string> shadowResources;
    if (shadowSet_.viewCount > 0) {
        shadowRows_.clear();
        for (shadows::ShadowPass& p : shadows_->passes()) {
            auto execute = std::move(p.execute);
            passes_.add({p.name.empty() ? "shadow" : "shadow." + p.name, p.reads, p.writes,
                         [this, execute] { execute(shadowFrame_); }});
            std::function<void(int, int)> rows;
            if (p.executeRows)
                rows = [this, bands = std::move(p.executeRows)](int y0, int y1) {
                    bands(shadowFrame_, y0, y1);
                };
            shadowRows_.push_back(std::move(rows));
        }
        shadowResources = shadows_->receiverResources();
    }
    shadowPassCount_ = passes_.passes().size(); // the first passes of the list
    auto plus = [](std::vector<std::string> a, const std::vector<std::string>& b) {
        a.insert(a.end(), b.begin(), b.end());
        return a;
    };
    auto bindShadows = [this] {
        if (shadowSet_.viewCount > 0) shadows_->bindForReceivers();
    };

    std::vector<std::string> opaqueReads = shadowResources;
    if (ao_) {
        // The opaque depth first (the same program with its colour masked and its shading
        // skipped: the same vertex transform, so the shaded pass's GL_LEQUAL test passes
        // exactly where the pre-pass wrote), then the AO of that depth.
        passes_.add({"depth", {}, {"depth"}, [this] {
                         opaqueFbo_.bind();
                         gpu::PipelineState state;
                         state.view(width_, height_).depth(GL_LESS, true);
                         state.colorMask[0] = glm::bvec4(false);
                         state_.apply(state);
                         const float one = 1.0f;
                         glClearNamedFramebufferfv(opaqueFbo_.id(), GL_DEPTH, 0, &one);
                         const gpu::Program& program = programs_.get(opaqueProgram_);
                         program.set("useOverride", 0).set("depthPrepass", 1);
                         drawObjects(program, Subset::Opaque);
                         glBindFramebuffer(GL_FRAMEBUFFER, 0);
                     }});
        passes_.add({"ao", {"depth"}, {"ao.depth", "ao.raw"}, [this] { ao_->estimate(depth_); }});
        passes_.add(
            {"ao.blur", {"ao.depth", "ao.raw"}, {"ao.visibility"}, [this] { ao_->blur(); }});
        opaqueReads.push_back("ao.visibility");
    }

    passes_.add({"opaque", opaqueReads, {"depth", "hdr"}, [this, bindShadows] {
                     bindShadows();
                     opaqueFbo_.bind();
                     gpu::PipelineState state;
                     state.view(width_, height_).depth(ao_ ? GL_LEQUAL : GL_LESS, true);
                     state_.apply(state); // before the clears: they obey the colour/depth masks
                     const glm::vec4 bg(scene_.render.background, 1.0f);
                     const float one = 1.0f;
                     glClearNamedFramebufferfv(opaqueFbo_.id(), GL_COLOR, 0, &bg.x);
                     if (!ao_) glClearNamedFramebufferfv(opaqueFbo_.id(), GL_DEPTH, 0, &one);
                     const gpu::Program& program = programs_.get(opaqueProgram_);
                     program.set("useOverride", 0);
                     if (ao_) {
                         program.set("depthPrepass", 0);
                         ao_->visibility().bind(VEIL_TEX_AO);
                     }
                     if (shadowSet_.viewCount > 0) shadows_->prepareReceiver(program, shadowFrame_);
                     drawObjects(program, Subset::Opaque);
                     glBindFramebuffer(GL_FRAMEBUFFER, 0);
                 }});

    // From here on the passes are per pixel (the tiled refinement runs them per tile).
    firstPerPixelPass_ = passes_.passes().size();
    std::vector<std::string> transparentReads = plus({"depth"}, shadowResources);
    if (ao_) transparentReads.push_back("ao.visibility"); // inferred AO (001 Listing 2)
    if (fog_) {
        passes_.add({"fog",
                     plus({"depth"}, shadowResources),
                     {"fog.light_transmittance", "fog.radiance"},
                     [this, bindShadows] {
                         bindShadows();
                         fog_->march(fogTargets_);
                     }});
        transparentReads.push_back("fog.radiance");
    }

    // The technique's accumulation targets are frame resources of their own (debug views,
    // --dump); oit.accumulation stands for its storage as a whole (lists, buffers).
    std::vector<std::string> accumulation =
        plus({"oit.accumulation"}, oit_->accumulationResources());
    passes_.add({"transparent", transparentReads, accumulation, [this, bindShadows] {
                     bindShadows();
                     setOitRegion();
                     for (int pass = 0; pass < oit_->geometryPasses(); ++pass) {
                         const gpu::Program& program = programs_.get(transparentPrograms_[pass]);
                         program.set("useOverride", 0);
                         if (shadowSet_.viewCount > 0)
                             shadows_->prepareReceiver(program, shadowFrame_);
                         oit_->beginAccumulate(pass, targets_, program);
                         const oit::PerPixelEmit fogMode = fog_ && !fog_->segmented()
                                                               ? oit_->perPixelEmit(pass)
                                                               : oit::PerPixelEmit::None;
                         if (fogMode != oit::PerPixelEmit::None) {
                             // Fog first: one contribution per pixel through the same oitEmit().
                             const gpu::Program& fogProgram = programs_.get(fogEmitPrograms_[pass]);
                             oit_->prepareProgram(pass, fogProgram);
                             fog_->bindForEmit(fogProgram, fogTargets_);
                             fogProgram.use();
                             if (fogMode == oit::PerPixelEmit::Compute) {
                                 oit_->bindPerPixelEmit(pass, targets_);
                                 fogProgram.set("emitRegion", region_); // a tile's pixels only
                                 glDispatchCompute((region_.z - region_.x + 7) / 8,
                                                   (region_.w - region_.y + 7) / 8, 1);
                                 // The pass's blending, texel fetches and image loads see it.
                                 glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT |
                                                 GL_TEXTURE_FETCH_BARRIER_BIT |
                                                 GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
                             } else {
                                 fog_->drawEmit();
                             }
                         }
                         drawObjects(program, Subset::Transparent);
                         if (fog_ && fog_->segmented() && pass + 1 == oit_->geometryPasses())
                             // After every surface is stored: the fog between them, per segment.
                             fog_->marchSegments(fogTargets_, [this, pass](const gpu::Program& p) {
                                 oit_->prepareProgram(pass, p);
                             });
                         oit_->endAccumulate(pass);
                         if (pass + 1 == oit_->geometryPasses() && oit_->repeatAccumulation())
                             pass = -1;
                     }
                 }});

    passes_.add(
        {"resolve", plus(accumulation, {"hdr"}), plus({"hdr"}, oit_->resolveResources()), [this] {
             setOitRegion();
             oit_->resolve(targets_);
         }});

    passes_.add({"tonemap", {"hdr"}, {"ldr"}, [this] {
                     const gpu::Program& program = programs_.get(tonemapProgram_);
                     program.use();
                     program.set("exposure", scene_.render.exposure)
                         .set("operatorId", scene_.render.tonemap == "clamp" ? 1 : 0)
                         .set("region", region_);
                     hdr_.bind(VEIL_TEX_HDR);
                     glBindImageTexture(VEIL_IMG_OUTPUT, ldr_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                                        GL_RGBA8);
                     glDispatchCompute((region_.z - region_.x + 7) / 8,
                                       (region_.w - region_.y + 7) / 8, 1);
                     glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
                 }});
    passes_.validate();
}

const gpu::Texture* Renderer::resourceTexture(const std::string& name) const {
    if (name == "depth") return &depth_;
    if (name == "hdr") return &hdr_;
    if (name == "ldr") return &ldr_;
    if (name.rfind("shadow.", 0) == 0) return shadows_->resourceTexture(name);
    if (ao_ && name.rfind("ao.", 0) == 0) return ao_->resourceTexture(name);
    if (fog_ && name == "fog.radiance")
        return fog_->perPixelMarchRuns() ? &fog_->radianceTexture() : nullptr;
    if (fog_ && name == "fog.light_transmittance") return fog_->lightTransmittanceTexture(0);
    if (name.rfind("oit.", 0) == 0) return oit_->resourceTexture(name);
    return nullptr;
}

gpu::ImageF Renderer::readHdr() const { return gpu::readTexture(hdr_); }
gpu::ImageF Renderer::readLdr() const { return gpu::readTexture(ldr_); }

std::size_t Renderer::gpuBytes() const {
    std::size_t bytes = static_cast<std::size_t>(width_) * height_ * (8 + 4 + 4);
    for (const auto& m : meshes_)
        bytes += m.gpuBytes();
    if (shadowSet_.viewCount > 0) bytes += shadows_->gpuBytes();
    bytes += static_cast<std::size_t>(width_) * height_ * oit_->bytesPerPixel();
    if (fog_) bytes += fog_->gpuBytes();
    if (ao_) bytes += ao_->gpuBytes();
    return bytes;
}

} // namespace veil::frame
