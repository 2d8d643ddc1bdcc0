#include "frame/renderer.h"

#include "base/error.h"
#include "base/log.h"

#include <limits>

namespace veil::frame {

namespace {
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
    oit_ = createOitTechnique(scene, options, context_, programs_);
    oitPrograms_ = programs_.handlesFrom(oitMark); // the technique's own (resolve, ...)
    scene.bounds(boundsLo_, boundsHi_);

    // The shadow technique, chosen like the OIT technique (render.shadows, --shadows).
    std::string shadowsWhere;
    shadows_ = createShadowTechnique(scene, options, context_, programs_, shadowsWhere);
    const Properties& sp = shadows_->properties();
    shadowSet_ = shadows::chooseShadowLights(scene, sp.getInt("max_lights"),
                                             fmt::format("{} (max_lights)", shadowsWhere));
    if (shadowSet_.viewCount > 0) {
        checkShadowWork(scene, context_, *shadows_, shadowsWhere, sp.getInt("size"),
                        shadowSet_.viewCount);
        shadows_->resize(sp.getInt("size"), shadowSet_.viewCount);
        if (auto request = shadows_->lightSliceMap())
            lightSlices_ =
                std::make_unique<voxelize::LightSliceMap>(programs_, std::move(*request));
    }

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
        // The light views hold the volumes too: they cast (into maps that replace the
        // marcher's self-shadowing) and receive (every fog sample asks the maps).
        if (scene.objects.empty()) {
            boundsLo_ = glm::vec3(std::numeric_limits<float>::max());
            boundsHi_ = glm::vec3(std::numeric_limits<float>::lowest());
        }
        fog_->extendBounds(boundsLo_, boundsHi_);
        if (boundsLo_.x > boundsHi_.x) boundsLo_ = boundsHi_ = glm::vec3(0.0f); // global fog only
    }
    if (fog_ && fog_->hasGridVolumes() && shadowSet_.viewCount > 0)
        shadows_->checkReceiverWork(context_, scene.render.fogSteps,
                                    static_cast<int>(shadowSet_.lights.size()), shadowsWhere);
    const std::size_t passMark = programs_.size();
    transparency_ = buildTransparencyPrograms(*oit_, fog_.get(), programs_, visibility);
    computeRaster_ = makeComputeRaster();
    for (gpu::ProgramHandle h : programs_.handlesFrom(passMark))
        oitPrograms_.push_back(h);

    meshes_.reserve(scene.meshes.size());
    for (const auto& mesh : scene.meshes)
        meshes_.emplace_back(mesh);

    if (scene.lights.size() > VEIL_MAX_LIGHTS)
        log::warn("scene has {} lights; only the first {} are used", scene.lights.size(),
                  VEIL_MAX_LIGHTS);

    shadowMapSize_ = sp.getInt("size");
    pass_.state = &state_;
    pass_.resources = &resources_;
    pass_.scene = &scene_;
    pass_.lightViews = &shadowViews_;
    pass_.seed = scene.render.seed;
    pass_.drawObjects = [this](const gpu::Program& program, pass::ObjectSet set) {
        drawObjects(scene_, meshes_, program, set);
    };
    pass_.objectTriangles = [this](pass::ObjectSet set) {
        return objectTriangles(scene_, meshes_, set);
    };
    pass_.dispatchObjects = [this](const gpu::Program& program, pass::ObjectSet set,
                                   const std::function<void(std::uint32_t, std::uint32_t)>& f) {
        dispatchObjects(scene_, meshes_, program, set, f);
    };
    if (fog_ && fog_->hasGridVolumes())
        pass_.bindMedia = [this](const gpu::Program& program) { fog_->bindVolumes(program); };

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

std::unique_ptr<oit::ComputeRaster> Renderer::makeComputeRaster() {
    if (scene_.render.oitRasterizer != "compute") return nullptr;
    return std::make_unique<oit::ComputeRaster>(
        programs_, *oit_,
        gpu::IncludeAliases{{"veil:raster_setup", "frame/raster_setup.glsl"},
                            {"veil:raster_surface", "frame/raster_surface.glsl"},
                            {"veil:raster_layout", "frame/raster_layout.glsl"},
                            {"veil:light_visibility", shadows_->visibilityInclude()}});
}

void Renderer::setOitTechnique(const std::string& name, const nlohmann::json& properties,
                               const std::string& where) {
    // Built aside first: a failure leaves the current technique and programs in place. Every
    // program added from `mark` on is the new technique's (its own, its transparent and fog
    // programs); the old technique's are released once the new one stands.
    const std::size_t mark = programs_.size();
    std::unique_ptr<oit::Technique> next;
    const std::string previousName = oitName_;
    const TransparencyPrograms previous = transparency_;
    std::unique_ptr<oit::ComputeRaster> previousRaster = std::move(computeRaster_);
    const volume::FogPass::SegmentsState segments =
        fog_ ? fog_->segmentsState() : volume::FogPass::SegmentsState{};
    try {
        next = oit::Registry::instance().create(name, context_, programs_, properties, where);
        std::swap(oit_, next);
        oitName_ = name;
        transparency_ =
            buildTransparencyPrograms(*oit_, fog_.get(), programs_,
                                      {{"veil:light_visibility", shadows_->visibilityInclude()}});
        computeRaster_ = makeComputeRaster();
        oit_->resize(pass_);
        rebuildPasses(); // the technique's targets are frame resources
    } catch (...) {
        for (gpu::ProgramHandle h : programs_.handlesFrom(mark))
            programs_.release(h);
        if (next) std::swap(oit_, next); // the previous technique back
        oitName_ = previousName;
        transparency_ = previous;
        computeRaster_ = std::move(previousRaster);
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
    pass_.width = width_;
    pass_.height = height_;
    pass_.hdrColor = &hdr_;
    pass_.depth = &depth_;
    if (ao_) {
        ao_->resize(width_, height_);
        pass_.ambientOcclusion = &ao_->visibility();
    }
    oit_->resize(pass_);
}

void Renderer::updateUniforms() {
    const CameraBlock cam = cameraBlock(camera_, width_, height_);
    cameraUbo_.setSubData(0, sizeof(cam), &cam);
    const LightsBlock block = lightsBlock(scene_, shadowSet_.lights);
    lightsUbo_.setSubData(0, sizeof(block), &block);

    // The shadowed lights' views, refitted every frame (lights and objects may move).
    shadowViews_ = shadows::fitViews(scene_, shadowSet_, boundsLo_, boundsHi_);
    shadows::ShadowsBlock sb{};
    shadows::fillShadowsBlock(sb, shadowViews_, shadowSet_, shadowMapSize_);
    shadows_->fillParams(sb);
    shadowsUbo_.setSubData(0, sizeof(sb), &sb);
}

void Renderer::render() {
    beginFrame();
    runLightPasses();
    runPasses(pass::Scope::Frame);
    runPasses(pass::Scope::Pixels);
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
    pass_.projection = camera_.projection(aspect);
    pass_.viewProjection = pass_.projection * camera_.view();
    pass_.orthographicCamera = camera_.type == scene::CameraType::Orthographic;
    pass_.prepareReceiver = nullptr;
    if (shadowSet_.viewCount > 0)
        pass_.prepareReceiver = [this](const gpu::Program& program) {
            shadows_->prepareReceiver(program, pass_);
        };
    setRegion(glm::ivec4(0, 0, width_, height_));
    skipShadowPasses_ =
        reuseShadowMaps_ && shadowMapsValid_ && hasLightPasses() && !shadows_->dependsOnCamera();
}

void Renderer::setRegion(glm::ivec4 region) {
    pass_.region = region;
    // Part of the frame (a refinement tile): hdr holds the opaque image inside it only.
    const bool part = region != glm::ivec4(0, 0, width_, height_);
    pass_.opaqueColor = part ? &opaqueHdr_ : nullptr;
}

bool Renderer::hasLightPasses() const {
    const std::vector<pass::Pass>& passes = passes_.passes();
    return !passes.empty() && passes.front().scope == pass::Scope::Lights;
}

void Renderer::runPass(const pass::Pass& p) {
    gpu::TimerScope t(timer_, p.name);
    if (p.receivesShadows && shadowSet_.viewCount > 0) shadows_->bindForReceivers();
    p.execute(pass_);
}

void Renderer::runPasses(pass::Scope scope) {
    for (const pass::Pass& p : passes_.passes())
        if (p.scope == scope) runPass(p);
}

void Renderer::runLightPasses() {
    if (!hasLightPasses()) return;
    if (skipShadowPasses_) { // the maps of an earlier frame stand
        ++shadowMapReuses_;
        return;
    }
    shadowMapsValid_ = false; // until every shadow pass ran (one may throw)
    runPasses(pass::Scope::Lights);
    shadowMapsValid_ = true;
    ++shadowMapRenders_;
}

gpu::ImageF Renderer::readHdr() const { return gpu::readTexture(hdr_); }
void Renderer::readHdrInto(float* pixels, std::size_t count) const {
    gpu::readTextureInto(hdr_, 4, pixels, count);
}
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
