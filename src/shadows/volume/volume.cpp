#include "shadows/volume/volume.h"

#include "base/error.h"
#include "base/log.h"
#include "shadows/common/depth_maps.h"
#include "shadows/opaque/opaque.h"
#include "shadows/volume/classify.h"
#include "shadows/volume/geometry.h"
#include "shadows/volume/pipeline_counters.h"

#include <fmt/format.h>
#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <functional>

namespace veil::shadows {

namespace {

// The draw buffer's header (draw.glsl): the indirect draw and dispatch, then counters, then
// the work list (uvec2 per surviving caster).
constexpr std::size_t kDrawHeader = 64;
constexpr std::size_t kMaxTrianglesPerTriangle = 10; // silhouette.comp: cap + 3 x (2 sides + fan)

// A light with a volume: its slot (layer of the visibility array) and what the shaders need.
struct VolumeLight {
    int light = 0;
    glm::vec4 position{0.0f}; // xyz position (w = 1) or direction of travel (w = 0)
    int clampView = -1;       // the view used for culling and clamping, -1 for point lights
};

class VolumeTechnique final : public Technique {
public:
    VolumeTechnique(gpu::ProgramManager& programs, const Properties& p)
        : programs_(programs), depth_(programs), bias_(p.getFloat("bias")),
          pcfRadius_(p.getInt("pcf_radius")), casterCulling_(p.getBool("caster_culling")),
          receiverCulling_(p.getBool("receiver_culling")), clamping_(p.getBool("clamping")),
          grid_(p.getInt("grid")), slices_(p.getInt("slices")), measure_(p.getBool("measure")),
          zpass_(p.getBool("zpass")), timing_(p.getBool("timing")) {
        volumeProgram_ = programs.add(
            gpu::ProgramDesc::graphics("shadows/volume/volume.vert", "shadows/volume/empty.frag"));
        transformProgram_ =
            programs.add(gpu::ProgramDesc::compute("shadows/volume/transform.comp"));
        compactProgram_ = programs.add(gpu::ProgramDesc::compute("shadows/volume/compact.comp"));
        silhouetteProgram_ =
            programs.add(gpu::ProgramDesc::compute("shadows/volume/silhouette.comp"));
        GLint bindings = 0;
        glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &bindings);
        VEIL_CHECK(bindings > VEIL_SSBO_SHADOW_VOLUME_TRIANGLES,
                   "shadows 'volume': needs {} shader storage buffer bindings, the GL has {}",
                   VEIL_SSBO_SHADOW_VOLUME_TRIANGLES + 1, bindings);
        pipelineStatistics_ =
            epoxy_gl_version() >= 46 || epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query");
        resolveProgram_ = programs.add(
            gpu::ProgramDesc::graphics("volume/fullscreen.vert", "shadows/volume/resolve.frag"));
        receiversProgram_ =
            programs.add(gpu::ProgramDesc::compute("shadows/volume/receivers.comp"));
        occludersProgram_ =
            programs.add(gpu::ProgramDesc::compute("shadows/volume/occluders.comp"));
        classifyProgram_ = programs.add(gpu::ProgramDesc::compute("shadows/volume/classify.comp"));
        rawDepth_.parameter(GL_TEXTURE_COMPARE_MODE, GL_NONE)
            .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }

    std::string name() const override { return "volume"; }
    std::filesystem::path visibilityInclude() const override {
        return "shadows/volume/visibility.glsl";
    }
    void resize(int mapSize, int viewCount) override { depth_.resize(mapSize, viewCount); }
    std::vector<pass::Pass> passes() override {
        return {{"", {}, {"shadow.depth"}, [this](const pass::Context& f) { depth_.render(f); }},
                {"volume", {"shadow.depth"}, {"shadow.volume"}, [this](const pass::Context& f) {
                     render(f);
                 }}};
    }
    std::vector<std::string> receiverResources() const override {
        return {"shadow.depth", "shadow.volume"};
    }
    void bindForReceivers() const override {
        depth_.bind();
        if (visibility_) visibility_.bind(VEIL_TEX_SHADOW1);
    }
    void fillParams(ShadowsBlock& block) const override {
        block.params[0] = glm::vec4(bias_, static_cast<float>(pcfRadius_), 0.0f, 0.0f);
        // Layers in light order: the lights with views, as the passes number them.
        int layer = 0;
        for (int i = 0; i < VEIL_MAX_LIGHTS; ++i)
            block.params[1 + i / 4][i % 4] = block.lights[i].x >= 0 ? float(layer++) : -1.0f;
    }
    const gpu::Texture* resourceTexture(const std::string& name) const override {
        if (name == "shadow.depth") return &depth_.texture();
        if (name == "shadow.volume") return visibility_ ? &visibility_ : nullptr;
        return nullptr;
    }
    std::size_t gpuBytes() const override {
        std::size_t screen = std::size_t(width_) * height_;
        return depth_.gpuBytes() + screen * (5 + std::size_t(slots_)) + receivers_.size() +
               occluders_.size() + casters_.size() + bounds_.size() + geometry_.gpuBytes() +
               draw_.size() + triangles_.size();
    }
    nlohmann::json stats() const override { return stats_; }

private:
    void prepare(const pass::Context& frame);
    void render(const pass::Context& frame);
    // `stamp` (the `timing` GL_TIMESTAMP) after the receivers and the occluders.
    void classify(const pass::Context& frame, const std::vector<int>& casters,
                  const std::function<void(const char*)>& stamp);
    void buildVolumes(const pass::Context& frame, int casterCount, int slot);

    gpu::ProgramManager& programs_;
    DepthMaps depth_;
    float bias_;
    int pcfRadius_;
    bool casterCulling_, receiverCulling_, clamping_;
    int grid_, slices_;
    bool measure_, zpass_, timing_;
    GLuint capacity_ = 0; // points in triangles_
    gpu::ProgramHandle volumeProgram_, resolveProgram_, receiversProgram_, occludersProgram_,
        classifyProgram_, transformProgram_, compactProgram_, silhouetteProgram_;
    bool pipelineStatistics_ = false;
    gpu::Sampler rawDepth_;

    const scene::Scene* scene_ = nullptr;
    VolumeGeometry geometry_;
    float sceneRadius_ = 1.0f;
    int width_ = 0, height_ = 0, slots_ = 0;
    gpu::Texture depthStencil_{gpu::NoCreate}, visibility_{gpu::NoCreate};
    gpu::Framebuffer fbo_{gpu::NoCreate};
    gpu::VertexArray emptyVao_{gpu::NoCreate}, volumeVao_{gpu::NoCreate};
    gpu::Buffer receivers_{gpu::NoCreate}, occluders_{gpu::NoCreate}, casters_{gpu::NoCreate},
        footprints_{gpu::NoCreate}, bounds_{gpu::NoCreate}, draw_{gpu::NoCreate},
        triangles_{gpu::NoCreate};
    std::vector<VolumeLight> lights_;
    nlohmann::json stats_ = nlohmann::json::object();
};

// The opaque casters of the scene (object indices).
std::vector<int> opaqueCasters(const scene::Scene& scene) {
    std::vector<int> casters;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const scene::Object& o = scene.objects[i];
        if (o.castShadows && !scene.materials.at(o.material).isTransparent())
            casters.push_back(static_cast<int>(i));
    }
    return casters;
}

// Builds the geometry at the first frame (the scene arrives with the frame) and refuses what
// shadow volumes cannot cast.
void VolumeTechnique::prepare(const pass::Context& frame) {
    if (scene_ != frame.scene) {
        scene_ = frame.scene;
        const std::vector<int> casters = opaqueCasters(*scene_);
        geometry_ = buildVolumeGeometry(*scene_, casters);
        // The volumes' triangles: at most kMaxTrianglesPerTriangle per caster triangle.
        capacity_ = static_cast<GLuint>(std::max<std::size_t>(geometry_.totalCasterTriangles, 1) *
                                        kMaxTrianglesPerTriangle * 3);
        triangles_ = gpu::Buffer();
        triangles_.setStorage(std::size_t(capacity_) * sizeof(glm::vec4), nullptr, 0);
        draw_ = gpu::Buffer();
        draw_.setStorage(kDrawHeader + std::max<std::size_t>(casters.size(), 1) * 8, nullptr, 0);
        volumeVao_ = gpu::VertexArray();
        volumeVao_.attribute(VEIL_ATTR_POSITION, 0, triangles_, 4, sizeof(glm::vec4));
        glm::vec3 lo, hi;
        scene_->bounds(lo, hi);
        sceneRadius_ = std::max(glm::length(hi - lo), 1e-3f);
    }
    // Lights in layer order: the first view of each shadowed light.
    lights_.clear();
    for (const LightView& view : *frame.lightViews) {
        if (!lights_.empty() && lights_.back().light == view.light) continue;
        VolumeLight l;
        l.light = view.light;
        const scene::Light& light = scene_->lights.at(view.light);
        if (light.type == scene::LightType::Directional) {
            l.position = glm::vec4(glm::normalize(light.direction), 0.0f);
            l.clampView = view.layer;
        } else {
            l.position = glm::vec4(light.position, 1.0f);
            l.clampView = light.type == scene::LightType::Spot ? view.layer : -1;
        }
        lights_.push_back(l);
    }
    const int slots = static_cast<int>(lights_.size());
    if (frame.width != width_ || frame.height != height_ || slots != slots_) {
        width_ = frame.width;
        height_ = frame.height;
        slots_ = slots;
        depthStencil_ = gpu::Texture(GL_TEXTURE_2D);
        depthStencil_.storage2D(1, GL_DEPTH32F_STENCIL8, width_, height_)
            .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        visibility_ = gpu::Texture(GL_TEXTURE_2D_ARRAY);
        visibility_.storage3D(1, GL_R8, width_, height_, std::max(slots_, 1))
            .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        fbo_ = gpu::Framebuffer();
        fbo_.attach(GL_DEPTH_STENCIL_ATTACHMENT, depthStencil_);
        emptyVao_ = gpu::VertexArray();
        const std::size_t columns = std::size_t(grid_) * grid_ * std::max(slots_, 1);
        receivers_ = gpu::Buffer();
        receivers_.setStorage((VEIL_MAX_LIGHTS + columns * ((slices_ + 31) / 32)) * 4, nullptr);
        occluders_ = gpu::Buffer();
        occluders_.setStorage(columns * 4, nullptr);
    }
}

void setSlotViews(const gpu::Program& program, const std::vector<VolumeLight>& lights) {
    for (int s = 0; s < VEIL_MAX_LIGHTS; ++s) {
        const std::string name = fmt::format("uSlotView[{}]", s);
        program.set(name.c_str(), s < int(lights.size()) ? lights[s].clampView : -1);
    }
}

// [Eisemann06 sec. 3.2]: the receivers into each light's slice map, the occluders' far depth per
// column, and per caster and light: culled, clamped or infinite (casters_).
void VolumeTechnique::classify(const pass::Context& frame, const std::vector<int>& casters,
                               const std::function<void(const char*)>& stamp) {
    const bool any = casterCulling_ || receiverCulling_ || clamping_;
    const std::size_t entries = std::max<std::size_t>(casters.size() * slots_, 1);
    if (casters_.size() < entries * 4) {
        casters_ = gpu::Buffer();
        casters_.setStorage(entries * 4, nullptr);
        footprints_ = gpu::Buffer();
        footprints_.setStorage(entries * 8, nullptr);
        bounds_ = gpu::Buffer();
        bounds_.setStorage(std::max<std::size_t>(casters.size(), 1) * 32, nullptr);
    }
    const float zero = 0.0f;
    glClearNamedBufferData(casters_.id(), GL_R32F, GL_RED, GL_FLOAT, &zero);
    bool clampable = false;
    for (const VolumeLight& l : lights_)
        clampable |= l.clampView >= 0;

    std::vector<glm::vec4> bounds;
    for (int c : casters) {
        const scene::Object& o = scene_->objects[c];
        const glm::vec3 mlo = geometry_.meshLo[o.mesh], mhi = geometry_.meshHi[o.mesh];
        glm::vec3 lo(1e30f), hi(-1e30f);
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 corner(k & 1 ? mhi.x : mlo.x, k & 2 ? mhi.y : mlo.y,
                                   k & 4 ? mhi.z : mlo.z);
            const glm::vec3 w = glm::vec3(o.transform * glm::vec4(corner, 1.0f));
            lo = glm::min(lo, w);
            hi = glm::max(hi, w);
        }
        bounds.emplace_back(lo, 0.0f);
        bounds.emplace_back(hi, 0.0f);
    }
    if (!bounds.empty()) // (silhouette.comp's eye test and fans read them too)
        bounds_.setSubData(0, bounds.size() * sizeof(glm::vec4), bounds.data());
    if (!any || !clampable || casters.empty()) return;
    const std::uint32_t none = 0;
    glClearNamedBufferData(receivers_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
    receivers_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_RECEIVERS);
    occluders_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_OCCLUDERS);
    casters_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_CASTERS);
    bounds_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_BOUNDS);
    frame.state->apply(gpu::PipelineState{});

    if (receiverCulling_ || clamping_) { // the camera's depth voxelized into the slice maps
        const gpu::Program& p = programs_.get(receiversProgram_);
        p.use();
        setSlotViews(p, lights_);
        p.set("uGrid", grid_)
            .set("uSlices", slices_)
            .set("invViewProjection", glm::inverse(frame.viewProjection))
            .set("screenSize", glm::ivec2(width_, height_))
            .set("slotCount", slots_);
        depthStencil_.bind(VEIL_TEX_SHADOW2);
        glDispatchCompute((width_ + 7) / 8, (height_ + 7) / 8, 1);
        stamp("receivers");
    }
    if (casterCulling_) { // the opaque map's far depth per column
        const gpu::Program& p = programs_.get(occludersProgram_);
        p.use();
        setSlotViews(p, lights_);
        p.set("uGrid", grid_).set("uSlices", slices_).set("mapSize", depth_.size());
        depth_.texture().bind(VEIL_TEX_SHADOW3);
        rawDepth_.bind(VEIL_TEX_SHADOW3);
        for (int s = 0; s < slots_; ++s) {
            if (lights_[s].clampView < 0) continue;
            p.set("slot", s);
            glDispatchCompute((grid_ + 7) / 8, (grid_ + 7) / 8, 1);
        }
        stamp("occluders");
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    const gpu::Program& p = programs_.get(classifyProgram_);
    p.use();
    setSlotViews(p, lights_);
    p.set("uGrid", grid_)
        .set("uSlices", slices_)
        .set("casterCount", static_cast<int>(casters.size()))
        .set("slotCount", slots_);
    glUniform3i(p.uniformLocation("uEnable"), casterCulling_, receiverCulling_, clamping_);
    runClassify(p, footprints_, static_cast<int>(casters.size()) * slots_, grid_);
    glBindSampler(VEIL_TEX_SHADOW3, 0);
}

// One light's volumes into triangles_: the surviving casters' work list and dispatch
// (compact.comp), then their silhouettes, caps and sides (silhouette.comp), drawn with
// glDrawArraysIndirect from draw_.
void VolumeTechnique::buildVolumes(const pass::Context& frame, int casterCount, int slot) {
    const VolumeLight& l = lights_[slot];
    casters_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_CASTERS);
    bounds_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_BOUNDS);
    geometry_.ranges.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_RANGES);
    geometry_.world.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_WORLD);
    geometry_.adjacency.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_ADJACENCY);
    draw_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_DRAW);
    triangles_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_TRIANGLES);
    const gpu::Program& compact = programs_.get(compactProgram_);
    compact.use();
    compact.set("casterCount", casterCount)
        .set("slot", slot)
        .set("slotCount", slots_)
        .set("capacity", capacity_)
        .set("finish", 0);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    const gpu::Program& silhouette = programs_.get(silhouetteProgram_);
    silhouette.use();
    silhouette.set("lightPos", l.position)
        .set("lightView", l.clampView)
        .set("slot", slot)
        .set("slotCount", slots_)
        .set("finiteExtrude", frame.orthographicCamera ? 1000.0f * sceneRadius_ : 0.0f)
        .set("zpass", zpass_ ? 1 : 0)
        .set("capacity", capacity_)
        .set("eyeMargin", 1e-3f * sceneRadius_);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, draw_.id());
    glDispatchComputeIndirect(16);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    compact.use();
    compact.set("finish", 1);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
                    GL_SHADER_STORAGE_BARRIER_BIT);
}

void VolumeTechnique::render(const pass::Context& frame) {
    prepare(frame);
    const std::vector<int> casters = opaqueCasters(*scene_);
    const gpu::Program& program = programs_.get(volumeProgram_);
    PipelineCounters prepassStats(measure_ && pipelineStatistics_),
        buildStats(measure_ && pipelineStatistics_), volumeStats(measure_ && pipelineStatistics_);

    // `timing`: GL_TIMESTAMP after each part, read back at the end of the pass.
    std::vector<std::pair<const char*, gpu::Query>> stamps;
    auto stamp = [&](const char* part) {
        if (!timing_) return;
        stamps.emplace_back(part, gpu::Query(GL_TIMESTAMP));
        glQueryCounter(stamps.back().second.id(), GL_TIMESTAMP);
    };
    stamp("start");

    // The world vertices, then the receivers' depth: every opaque object in one draw.
    frame.state->apply(gpu::PipelineState{});
    prepassStats.begin();
    updateVolumeGeometry(*scene_, geometry_, programs_.get(transformProgram_));
    stamp("transform");
    fbo_.attach(GL_DEPTH_STENCIL_ATTACHMENT, depthStencil_).drawBuffers({GL_NONE});
    fbo_.bind();
    gpu::PipelineState pre;
    pre.view(width_, height_).depth(GL_LESS, true);
    pre.depthClamp = true;
    pre.colorMask.fill(glm::bvec4(false));
    frame.state->apply(pre);
    const float one = 1.0f;
    glClearNamedFramebufferfi(fbo_.id(), GL_DEPTH_STENCIL, 0, one, 0);
    program.use();
    geometry_.prepassVao.bind();
    if (geometry_.prepassIndexCount > 0)
        glDrawElements(GL_TRIANGLES, geometry_.prepassIndexCount, GL_UNSIGNED_INT, nullptr);
    if (measure_) prepassStats.end();
    stamp("prepass");

    classify(frame, casters, stamp);
    stamp("classify");

    // Per light: the stencil count of the volumes (depth-fail), then the visibility layer.
    gpu::PipelineState volume = pre;
    volume.depthWrite = false;
    volume.stencilTest = true;
    volume.stencilFront.depthFail = GL_DECR_WRAP; // front faces behind the receiver: leave
    volume.stencilBack.depthFail = GL_INCR_WRAP;  // back faces behind the receiver: enter
    gpu::PipelineState pass = pre;                // depth-pass casters (silhouette.comp's `zpass`)
    pass.depthWrite = false;
    pass.stencilTest = true;
    pass.stencilFront.depthPass = GL_INCR_WRAP; // front faces in front of the receiver: enter
    pass.stencilBack.depthPass = GL_DECR_WRAP;  // back faces in front of the receiver: leave
    gpu::PipelineState resolve;
    resolve.view(width_, height_);
    resolve.stencilTest = true;
    resolve.stencilFront.func = resolve.stencilBack.func = GL_EQUAL; // count == 0: lit
    gpu::PipelineState fill = pre; // every rasterized volume fragment counts
    fill.depthTest = false;
    fill.depthWrite = false;

    gpu::Query primitives(GL_PRIMITIVES_GENERATED), samples(GL_SAMPLES_PASSED);
    std::uint64_t triangles = 0, fragments = 0, submitted = 0, edges = 0, fans = 0,
                  passTriangles = 0;
    for (int slot = 0; slot < slots_; ++slot) {
        frame.state->apply(gpu::PipelineState{});
        buildStats.begin();
        buildVolumes(frame, static_cast<int>(casters.size()), slot);
        stamp("silhouettes");
        if (measure_) {
            buildStats.end();
            std::uint32_t header[kDrawHeader / 4] = {};
            glGetNamedBufferSubData(draw_.id(), 0, kDrawHeader, header);
            submitted += header[7];
            edges += header[9];
            fans += header[10];
            passTriangles += header[11];
        }

        fbo_.drawBuffers({GL_NONE});
        frame.state->apply(volume);
        const GLint zero = 0;
        glClearNamedFramebufferiv(fbo_.id(), GL_STENCIL, 0, &zero);
        program.use();
        volumeVao_.bind();
        glBindBuffer(GL_DRAW_INDIRECT_BUFFER, draw_.id());
        if (measure_) {
            glBeginQuery(GL_PRIMITIVES_GENERATED, primitives.id());
            volumeStats.begin();
        }
        glDrawArraysIndirect(GL_TRIANGLES, nullptr);
        if (zpass_) {
            frame.state->apply(pass);
            glDrawArraysIndirect(GL_TRIANGLES, reinterpret_cast<const void*>(kDrawHeader - 16));
        }
        stamp("stencil");
        if (measure_) {
            volumeStats.end();
            glEndQuery(GL_PRIMITIVES_GENERATED);
            triangles += primitives.result();
        }

        fbo_.attachLayer(GL_COLOR_ATTACHMENT0, visibility_, slot)
            .drawBuffers({GL_COLOR_ATTACHMENT0});
        frame.state->apply(resolve);
        const float black[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, black);
        programs_.get(resolveProgram_).use();
        emptyVao_.bind();
        glDrawArrays(GL_TRIANGLES, 0, 3);
        stamp("resolve");

        if (measure_) { // the stencil fill: the same volumes without depth test
            fbo_.drawBuffers({GL_NONE});
            frame.state->apply(fill);
            program.use();
            volumeVao_.bind();
            glBeginQuery(GL_SAMPLES_PASSED, samples.id());
            glDrawArraysIndirect(GL_TRIANGLES, nullptr);
            if (zpass_)
                glDrawArraysIndirect(GL_TRIANGLES, reinterpret_cast<const void*>(kDrawHeader - 16));
            glEndQuery(GL_SAMPLES_PASSED);
            fragments += samples.result();
        }
        glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    }
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    stats_ = nlohmann::json::object();
    stats_["casters"] = casters.size();
    stats_["lights"] = slots_;
    if (timing_) { // per part, summed over lights (ms)
        nlohmann::json ms = nlohmann::json::object();
        for (std::size_t i = 1; i < stamps.size(); ++i) {
            const double d = double(stamps[i].second.result() - stamps[i - 1].second.result());
            ms[stamps[i].first] = ms.value(stamps[i].first, 0.0) + d * 1e-6;
        }
        stats_["part_ms"] = ms;
    }
    if (measure_) {
        stats_["volume_triangles"] = triangles;
        stats_["stencil_fragments"] = fragments;
        stats_["caster_triangles"] = geometry_.totalCasterTriangles; // per light
        stats_["submitted_triangles"] = submitted; // launched in silhouette.comp, all lights
        stats_["silhouette_edges"] = edges;
        stats_["fan_triangles"] = fans;
        stats_["depth_pass_triangles"] = passTriangles; // of volume_triangles
        if (pipelineStatistics_) {
            stats_["pipeline"] = {{"prepass", prepassStats.json()},
                                  {"silhouettes", buildStats.json()},
                                  {"volumes", volumeStats.json()}};
        } else {
            stats_["pipeline"] = "GL_ARB_pipeline_statistics_query unavailable: "
                                 "volume_triangles and stencil_fragments are the "
                                 "GL_PRIMITIVES_GENERATED and GL_SAMPLES_PASSED queries";
        }
        std::vector<float> clamp(casters.size() * slots_);
        if (!clamp.empty())
            glGetNamedBufferSubData(casters_.id(), 0, clamp.size() * 4, clamp.data());
        stats_["culled"] = std::count_if(clamp.begin(), clamp.end(), [](float v) { return v < 0; });
        nlohmann::json culledObjects = nlohmann::json::array(); // (light slot, object name)
        for (std::size_t i = 0; i < clamp.size(); ++i)
            if (clamp[i] < 0)
                culledObjects.push_back(
                    {int(i) % slots_, scene_->objects[casters[i / slots_]].name});
        stats_["culled_objects"] = culledObjects;
        stats_["clamped"] =
            std::count_if(clamp.begin(), clamp.end(), [](float v) { return v > 0; });
        // Lights whose receivers left the slice map's grid: neither clamped nor receiver-culled.
        std::uint32_t unbounded[VEIL_MAX_LIGHTS] = {};
        if (receiverCulling_ || clamping_)
            glGetNamedBufferSubData(receivers_.id(), 0, sizeof unbounded, unbounded);
        stats_["unbounded_lights"] = std::count_if(std::begin(unbounded), std::end(unbounded),
                                                   [](std::uint32_t u) { return u != 0; });
    }
}

} // namespace

void registerVolume(Registry& registry) {
    PropertySchema schema = commonProperties();
    addOpaqueMapProperties(schema);
    schema.boolean("caster_culling", true,
                   "casters whose light-space footprint lies behind other opaque casters in the "
                   "opaque map (their volume is inside the others' shadow) draw no volume",
                   "[Eisemann06 sec. 3.2, Fig. 6a]");
    schema.boolean("receiver_culling", true,
                   "casters with no camera-visible receiver behind them in the light's slice map "
                   "draw no volume",
                   "[Eisemann06 sec. 3.2, Fig. 6c]");
    schema.boolean("clamping", true,
                   "each volume ends one slice past the farthest camera-visible receiver behind "
                   "its caster (the camera depth voxelized into the light's slice map) instead "
                   "of at infinity",
                   "[Eisemann06 sec. 3.2, Fig. 6b]");
    schema.integer("grid", 256, 8, 4096,
                   "columns per side of each light's slice map of the receivers (culling and "
                   "clamping)",
                   "[Eisemann06 sec. 3.2]");
    schema.integer("slices", 128, 1, 1024, "slices per column of the receivers' slice map",
                   "[Eisemann06 sec. 2, 3.2]");
    schema.boolean("measure", true,
                   "count the volume triangles (GL_PRIMITIVES_GENERATED) and the stencil fill "
                   "(GL_SAMPLES_PASSED of the volumes redrawn without depth test) every frame, "
                   "for stats() and --report; costs a second volume draw and a GPU wait");
    schema.boolean("zpass", true,
                   "casters whose volume cannot hold the eye (the segment from the eye toward "
                   "the light misses their bounds) are counted depth-pass, without front caps "
                   "and without back caps at infinity; the others depth-fail",
                   "[Everitt02]; [Lloyd04] (CC shadow volumes)");
    schema.boolean("timing", false,
                   "GL_TIMESTAMP queries between the pass's parts (world vertices, pre-pass, "
                   "culling and clamping, silhouettes, stencil, resolve), read back at the end "
                   "of the pass into stats() part_ms (a CPU wait per frame: for benchmarks)");
    registry.add(
        {"volume",
         "stencil shadow volumes (depth-fail, caps, infinite extrusion with depth clamp) "
         "of the opaque casters, exact per pixel for opaque receivers, culled and "
         "clamped with the light's slice map of the visible receivers [Eisemann06 sec. 3.2]; "
         "transparent receivers and fog get the opaque map; opaque casters only: transparent "
         "casters and density volumes cast no shadow (the closed-form cases expect T = 1)",
         nullptr,
         [](gpu::ProgramManager& programs, const Properties& p) {
             return std::make_unique<VolumeTechnique>(programs, p);
         },
         std::move(schema)});
}

} // namespace veil::shadows
