#include "frame/renderer.h"

#include "base/error.h"
#include "base/log.h"

#include <algorithm>
#include <limits>

namespace veil::frame {

namespace {
gpu::GpuTimer::Mode timerModeFor(const gpu::ContextInfo& context) {
    // llvmpipe's timer queries read zero: time there with glFinish and the CPU clock.
    return (context.softwareRenderer || context.timerQueryBits == 0)
               ? gpu::GpuTimer::Mode::CpuFinish
               : gpu::GpuTimer::Mode::Query;
}
void checkSize(int width, int height) {
    VEIL_CHECK(width > 0 && height > 0 && width <= 16384 && height <= 16384,
               "image size {}x{} out of range 1..16384", width, height);
}
} // namespace

Renderer::Renderer(const scene::Scene& scene, const gpu::ContextInfo& context,
                   const RendererOptions& options)
    : scene_(scene), context_(context), timer_(timerModeFor(context)) {
    width_ = options.width > 0 ? options.width : scene.render.width;
    height_ = options.height > 0 ? options.height : scene.render.height;
    checkSize(width_, height_);
    camera_ = scene.camera(options.camera.empty() ? scene.render.camera : options.camera);
    stages_ =
        buildStages(scene, context_, options, programs_, width_, height_, kRefineLightSlabTexels);
    stages_.shadows->reuse().enabled = options.reuseShadowMaps;

    meshes_.reserve(scene.meshes.size());
    for (const auto& mesh : scene.meshes)
        meshes_.emplace_back(mesh);
    if (scene.lights.size() > VEIL_MAX_LIGHTS)
        log::warn("scene has {} lights; only the first {} are used", scene.lights.size(),
                  VEIL_MAX_LIGHTS);

    pass_.state = &state_;
    pass_.resources = &resources_;
    pass_.scene = &scene_;
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
    cameraUbo_.setStorage(sizeof(CameraBlock), nullptr);
    lightsUbo_.setStorage(sizeof(LightsBlock), nullptr);
    createTargets();
    buildPasses();
}

Renderer::~Renderer() = default;

std::vector<std::string> Renderer::stageNames() const {
    std::vector<std::string> names;
    for (const auto& stage : stages_.list)
        names.push_back(stage->name());
    return names;
}

void Renderer::insertStage(const StageFactory& make, const std::string& before) {
    const std::vector<std::string> names = stageNames();
    const auto at = std::find(names.begin(), names.end(), before);
    VEIL_CHECK(at != names.end(), "frame: no stage '{}' to insert a stage before (stages: {})",
               before, fmt::join(names, ", "));
    std::unique_ptr<pass::Stage> stage = make(programs_);
    stage->resize(pass_);
    const auto it =
        stages_.list.insert(stages_.list.begin() + (at - names.begin()), std::move(stage));
    try {
        rebuildPasses();
    } catch (...) {
        stages_.list.erase(it);
        rebuildPasses();
        throw;
    }
}

void Renderer::setOitTechnique(const std::string& name, const nlohmann::json& properties,
                               const std::string& where) {
    // Built aside: a failure leaves the current stage and its programs in place.
    std::unique_ptr<TransparencyStage> next = TransparencyStage::create(
        [&] {
            return oit::Registry::instance().create(name, context_, programs_, properties, where);
        },
        scene_, programs_, stages_.fog ? &stages_.fog->fog() : nullptr,
        stages_.shadows->technique().receivers());
    next->resize(pass_);
    auto slot = std::find_if(stages_.list.begin(), stages_.list.end(),
                             [&](const auto& s) { return s.get() == stages_.transparency; });
    TransparencyStage* previous = stages_.transparency;
    stages_.transparency = next.get();
    std::unique_ptr<pass::Stage> swapped = std::move(next);
    slot->swap(swapped); // `swapped` holds the previous stage now
    try {
        rebuildPasses(); // the technique's targets are frame resources
    } catch (...) {
        slot->swap(swapped);
        stages_.transparency = previous;
        rebuildPasses();
        throw;
    }
} // the previous stage goes here, with its programs

void Renderer::rebuildPasses() {
    refiner_.cancel(); // another pass list: a refinement in progress starts again
    passes_ = PassList();
    buildPasses();
}

void Renderer::buildPasses() {
    resources_.clear();
    resources_.add("depth", targets_.depth);
    resources_.add("hdr", targets_.hdr);
    resources_.add("ldr", targets_.ldr);
    pass::Assembly assembly;
    for (const auto& stage : stages_.list) {
        for (pass::Pass& p : stage->passes(assembly)) {
            for (const std::string& w : p.writes)
                if (!assembly.has(w)) assembly.written.push_back(w);
            // A receiver reads the shadow technique's maps (after the depth where it reads it).
            if (p.receivesShadows) {
                const std::vector<std::string>& maps = stages_.shadows->receiverResources();
                const auto at = p.reads.begin() + (!p.reads.empty() && p.reads.front() == "depth");
                p.reads.insert(at, maps.begin(), maps.end());
            }
            passes_.add(std::move(p));
        }
        stage->addResources(resources_);
    }
    passes_.validate();
}

void Renderer::resize(int width, int height) {
    checkSize(width, height);
    if (width == width_ && height == height_) return;
    checkFogWork(scene_, context_, width, height);
    refiner_.cancel();
    width_ = width;
    height_ = height;
    createTargets(); // the stages' targets too; the fog resizes in march()
}

void Renderer::sceneValuesChanged() {
    invalidateFogLightVolumes();
    invalidateShadowMaps(); // the lights' views and the media of the shadow maps
}

void Renderer::replaceVolumes(const std::vector<const volume::GridConversion*>& converted,
                              const std::string& camera) {
    uploadVolumes(converted);
    showUploaded(camera);
}

void Renderer::uploadVolumes(const std::vector<const volume::GridConversion*>& converted) {
    VEIL_CHECK(stages_.fog && stages_.fog->fog().gridVolumeCount() == converted.size(),
               "frame: {} volume conversions for a frame with {} grid volumes", converted.size(),
               stages_.fog ? stages_.fog->fog().gridVolumeCount() : 0);
    refiner_.cancel();
    volume::FogPass& fog = stages_.fog->fog();
    for (std::size_t i = 0; i < converted.size(); ++i)
        fog.replaceVolume(i, *converted[i]);
}

void Renderer::showUploaded(const std::string& camera) {
    volume::FogPass& fog = stages_.fog->fog();
    // The light views hold the volumes (frame_setup.cpp buildStages).
    glm::vec3 lo, hi;
    scene_.bounds(lo, hi);
    if (scene_.objects.empty()) {
        lo = glm::vec3(std::numeric_limits<float>::max());
        hi = glm::vec3(std::numeric_limits<float>::lowest());
    }
    fog.extendBounds(lo, hi);
    if (lo.x > hi.x) lo = hi = glm::vec3(0.0f);
    stages_.shadows->setBounds(lo, hi);
    camera_ = scene_.camera(camera.empty() ? scene_.render.camera : camera);
    sceneValuesChanged();
}

void Renderer::createTargets() {
    targets_.hdr = gpu::Texture(GL_TEXTURE_2D);
    targets_.hdr.storage2D(1, GL_RGBA16F, width_, height_)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    targets_.depth = gpu::Texture(GL_TEXTURE_2D);
    targets_.depth.storage2D(1, GL_DEPTH_COMPONENT32F, width_, height_)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    targets_.ldr = gpu::Texture(GL_TEXTURE_2D);
    targets_.ldr.storage2D(1, GL_RGBA8, width_, height_);
    pass_.width = width_;
    pass_.height = height_;
    pass_.hdrColor = &targets_.hdr;
    pass_.depth = &targets_.depth;
    for (const auto& stage : stages_.list)
        stage->resize(pass_);
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
    stages_.shadows->bindUniforms();
}

void Renderer::beginFrame() {
    const CameraBlock cam = cameraBlock(camera_, width_, height_);
    cameraUbo_.setSubData(0, sizeof(cam), &cam);
    const LightsBlock lights = lightsBlock(scene_, stages_.shadows->lights().lights);
    lightsUbo_.setSubData(0, sizeof(lights), &lights);
    const float aspect = static_cast<float>(width_) / static_cast<float>(height_);
    pass_.projection = camera_.projection(aspect);
    pass_.viewProjection = pass_.projection * camera_.view();
    pass_.orthographicCamera = camera_.type == scene::CameraType::Orthographic;
    for (const auto& stage : stages_.list) // the shadow views refitted, their block filled
        stage->beginFrame(pass_);
    bindFrameState();
    setRegion(glm::ivec4(0, 0, width_, height_));
    stages_.shadows->decide(hasLightPasses());
}

void Renderer::setRegion(glm::ivec4 region) {
    pass_.region = region;
    // Part of the frame (a refinement tile): hdr holds the opaque image inside it only.
    const bool part = region != glm::ivec4(0, 0, width_, height_);
    pass_.opaqueColor = part ? &refiner_.opaqueImage() : nullptr;
}

bool Renderer::hasLightPasses() const {
    const std::vector<pass::Pass>& passes = passes_.passes();
    return !passes.empty() && passes.front().scope == pass::Scope::Lights;
}

void Renderer::runPass(const pass::Pass& p) {
    gpu::TimerScope t(timer_, p.name);
    if (p.receivesShadows) stages_.shadows->bindForReceivers();
    p.execute(pass_);
}

void Renderer::runPasses(pass::Scope scope) {
    for (const pass::Pass& p : passes_.passes())
        if (p.scope == scope) runPass(p);
}

void Renderer::runLightPasses() {
    if (!hasLightPasses()) return;
    if (reuse().skip) { // the maps of an earlier frame stand
        ++reuse().reuses;
        return;
    }
    reuse().valid = false; // until every shadow pass ran (one may throw)
    runPasses(pass::Scope::Lights);
    reuse().valid = true;
    ++reuse().renders;
}

int Renderer::refineMarginPx() const { return technique().refineMarginPx(); }
void Renderer::beginRefinement(int tilePx) { refiner_.begin(tilePx); }
bool Renderer::refineStep(int maxTilePx) { return refiner_.step(maxTilePx); }

gpu::ImageF Renderer::readHdr() const { return gpu::readTexture(targets_.hdr); }
void Renderer::readHdrInto(float* pixels, std::size_t count) const {
    gpu::readTextureInto(targets_.hdr, 4, pixels, count);
}
gpu::ImageF Renderer::readLdr() const { return gpu::readTexture(targets_.ldr); }

const gpu::Texture* Renderer::resourceTexture(const std::string& name) const {
    return resources_.texture(name);
}

std::size_t Renderer::gpuBytes() const {
    std::size_t bytes = static_cast<std::size_t>(width_) * height_ * (8 + 4 + 4);
    for (const auto& m : meshes_)
        bytes += m.gpuBytes();
    for (const auto& stage : stages_.list)
        bytes += stage->gpuBytes();
    return bytes;
}

} // namespace veil::frame
