#include "shadows/transmittance_slicemap/transmittance_slicemap.h"

#include "base/error.h"
#include "shadows/common/depth_maps.h"
#include "shadows/common/fog_depth.h"
#include "shadows/opaque/opaque.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace veil::shadows {

namespace slicemap {

glm::dvec3 surfaceTransmittance(const scene::Material& m) {
    const double a = m.alpha;
    return glm::dvec3(1.0 - a) + a * glm::dvec3(m.transmission);
}

std::vector<glm::dvec3> groupClasses(const std::vector<glm::dvec3>& transmittances, int maxClasses,
                                     std::vector<int>* assignment) {
    VEIL_CHECK(maxClasses >= 1, "transmittance classes: {} must be at least 1", maxClasses);
    struct Cluster {
        glm::dvec3 absorbance{0.0}; // sum of -log T of the members
        int count = 0;
        std::vector<int> members;
        glm::dvec3 mean() const { return absorbance / double(count); }
    };
    const auto absorbance = [](const glm::dvec3& t) {
        return -glm::log(glm::max(t, glm::dvec3(1e-4)));
    };
    std::vector<Cluster> clusters;
    for (std::size_t i = 0; i < transmittances.size(); ++i) {
        const glm::dvec3 a = absorbance(transmittances[i]);
        auto it = std::find_if(clusters.begin(), clusters.end(), [&](const Cluster& c) {
            const glm::dvec3 d = glm::abs(glm::exp(-c.mean()) - transmittances[i]);
            return std::max({d.x, d.y, d.z}) < 1e-4;
        });
        if (it == clusters.end()) {
            clusters.push_back({});
            it = clusters.end() - 1;
        }
        it->absorbance += a;
        it->count += 1;
        it->members.push_back(static_cast<int>(i));
    }
    while (static_cast<int>(clusters.size()) > maxClasses) {
        std::size_t bi = 0, bj = 1;
        double best = 1e300;
        for (std::size_t i = 0; i < clusters.size(); ++i)
            for (std::size_t j = i + 1; j < clusters.size(); ++j) {
                const glm::dvec3 d = clusters[i].mean() - clusters[j].mean();
                // Ward-like cost: merging big classes moves more receivers.
                const double w = double(clusters[i].count) * clusters[j].count /
                                 (clusters[i].count + clusters[j].count);
                const double cost = w * glm::dot(d, d);
                if (cost < best) {
                    best = cost;
                    bi = i;
                    bj = j;
                }
            }
        clusters[bi].absorbance += clusters[bj].absorbance;
        clusters[bi].count += clusters[bj].count;
        clusters[bi].members.insert(clusters[bi].members.end(), clusters[bj].members.begin(),
                                    clusters[bj].members.end());
        clusters.erase(clusters.begin() + static_cast<std::ptrdiff_t>(bj));
    }
    std::vector<glm::dvec3> out;
    if (assignment) assignment->assign(transmittances.size(), 0);
    for (std::size_t c = 0; c < clusters.size(); ++c) {
        out.push_back(glm::exp(-clusters[c].mean()));
        if (assignment)
            for (int m : clusters[c].members)
                (*assignment)[m] = static_cast<int>(c);
    }
    return out;
}

std::vector<glm::dvec3> casterTransmittances(const scene::Scene& scene) {
    std::vector<glm::dvec3> t;
    for (const auto& object : scene.objects) {
        const scene::Material& m = scene.materials.at(object.material);
        if (object.castShadows && m.isTransparent()) t.push_back(surfaceTransmittance(m));
    }
    return t;
}

} // namespace slicemap

namespace {

class TransmittanceSlicemapTechnique final : public Technique {
public:
    TransmittanceSlicemapTechnique(gpu::ProgramManager& programs, const Properties& p)
        : depth_(programs), bias_(p.getFloat("bias")), pcfRadius_(p.getInt("pcf_radius")),
          slices_(p.getInt("slices")), local_(p.getBool("local_slicing")),
          maxClasses_(p.getInt("classes")), fog_(p.getBool("fog")) {
        const std::string method = p.getString("method");
        VEIL_CHECK(method == "raster" || method == "conservative",
                   "transmittance-slicemap: method '{}' is not available for light views (it "
                   "voxelizes CPU triangles into a world-aligned orthographic grid; the casters "
                   "come from the frame's caster draw into perspective/oblique light views): "
                   "use raster or conservative",
                   method);
        method_ = method;
        if (fog_)
            fogMap_.emplace(programs, p.getInt("fog_columns"), slices_, p.getInt("fog_substeps"));
    }

    std::string name() const override { return "transmittance-slicemap"; }
    std::filesystem::path visibilityInclude() const override {
        return "shadows/transmittance_slicemap/visibility.glsl";
    }
    void resize(int mapSize, int viewCount) override {
        depth_.resize(mapSize, viewCount);
        if (mapSize == size_ && viewCount == views_) return;
        size_ = mapSize;
        views_ = viewCount;
        wordsBytes_ = 0;
        if (fogMap_) fogMap_->resize(mapSize, viewCount);
    }
    // The slice map of the transparent casters: the frame's voxelize pass writes it (the
    // resource shadow.slices) before these passes, with this technique's class grouping
    // (asked once per run of that pass: classT_ then holds this frame's classes).
    std::optional<pass::LightSliceMapRequest> lightSliceMap() override {
        pass::LightSliceMapRequest r;
        r.name = "shadow.slices";
        r.owner = name();
        r.caster = "shadows/transmittance_slicemap/caster.frag";
        r.method = method_;
        r.size = size_;
        r.views = views_;
        r.slices = slices_;
        r.local = local_;
        r.classes = [this](const scene::Scene& scene) {
            const std::vector<glm::dvec3> ts = slicemap::casterTransmittances(scene);
            classT_ =
                ts.empty() ? std::vector<glm::dvec3>{} : slicemap::groupClasses(ts, maxClasses_);
            wordsBytes_ = std::size_t(views_) * std::max(classCount(), 1) * size_ * size_ *
                          ((slices_ + 31) / 32) * 4;
            std::vector<glm::vec3> t;
            for (const glm::dvec3& c : classT_)
                t.emplace_back(c);
            return t;
        };
        return r;
    }
    // Bands of texel rows (pass::Pass::executeRows) for the depth and fog passes.
    std::vector<pass::Pass> passes() override {
        std::vector<pass::Pass> p = {
            {"",
             {},
             {"shadow.depth"},
             [this](const pass::Context& f) { depth_.render(f); },
             [this](const pass::Context& f, int y0, int y1) { depth_.renderRows(f, y0, y1); }}};
        if (fog_) p.push_back(fogMap_->pass());
        return p;
    }
    std::vector<std::string> receiverResources() const override {
        if (fog_) return {"shadow.depth", "shadow.slices", "shadow.fog"};
        return {"shadow.depth", "shadow.slices"};
    }
    bool attenuatesMedia() const override { return fog_; }
    void bindForReceivers() const override {
        depth_.bind();
        if (fogMap_) fogMap_->bind();
    }
    void fillParams(ShadowsBlock& block) const override {
        block.params[0] = glm::vec4(bias_, float(pcfRadius_), float(slices_), local_ ? 1.0f : 0.0f);
    }
    // The classes and the fog come from this frame's passes (they run before every
    // receiver; the shadows block is filled before them): uniforms of the receiver. The slice
    // map (its words and local slicing's range) from the frame's resources.
    void prepareReceiver(const gpu::Program& program, const pass::Context& frame) const override {
        if (frame.resources) {
            if (const gpu::Texture* range = frame.resources->texture("shadow.slices.range"))
                range->bind(VEIL_TEX_SHADOW1);
            if (const gpu::Buffer* words = frame.resources->buffer("shadow.slices"))
                words->bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_SLICES);
        }
        std::vector<glm::vec3> t(3, glm::vec3(1.0f));
        for (int c = 0; c < classCount(); ++c)
            t[c] = glm::vec3(classT_[c]);
        program.set("slmClasses", classCount());
        if (fogMap_)
            fogMap_->prepareReceiver(program);
        else
            program.set("shadowFog", 0);
        glProgramUniform3fv(program.id(), program.uniformLocation("slmClassT"), 3, &t[0].x);
    }
    const gpu::Texture* resourceTexture(const std::string& name) const override {
        if (name == "shadow.depth") return &depth_.texture();
        if (name == "shadow.fog" && fogMap_) return &fogMap_->texture();
        return nullptr;
    }
    // Slices of the casters and of the media along the light views: no camera.
    bool dependsOnCamera() const override { return false; }
    // With the slice map the voxelize pass keeps for this technique (words, range, targets).
    std::size_t gpuBytes() const override {
        const std::size_t targets = std::min(8, (std::min(slices_, 1024) + 127) / 128);
        return depth_.gpuBytes() + wordsBytes_ + (fogMap_ ? fogMap_->gpuBytes() : 0) +
               std::size_t(size_) * size_ * (8 + 16 * targets) * std::max(views_, 1);
    }
    // The fog pass: fog_columns^2 columns x views x (slices + 1) slices x fog_substeps density
    // samples (common/fog_depth.comp), when there are grid volumes to march.
    WorkEstimate work(int mapSize, int viewCount, bool media) const override {
        (void)mapSize;
        return fogMap_ ? fogMap_->work(viewCount, media) : WorkEstimate{};
    }
    nlohmann::json stats() const override {
        nlohmann::json classes = nlohmann::json::array();
        for (const auto& t : classT_)
            classes.push_back({t.x, t.y, t.z});
        return {{"slices", slices_},
                {"local_slicing", local_},
                {"classes", classes},
                {"occupied_words_bytes", wordsBytes_}};
    }

private:
    int classCount() const { return static_cast<int>(classT_.size()); }

    DepthMaps depth_;
    float bias_;
    int pcfRadius_, slices_;
    bool local_;
    int maxClasses_;
    bool fog_;
    std::string method_;
    std::optional<FogDepthMap> fogMap_;
    int size_ = 0, views_ = 0;
    std::size_t wordsBytes_ = 0; // the slice map's words, once the voxelize pass ran
    std::vector<glm::dvec3> classT_;
};

} // namespace

void registerTransmittanceSlicemap(Registry& registry) {
    PropertySchema schema = commonProperties(1024);
    addOpaqueMapProperties(schema);
    schema.integer("slices", 128, 1, 1024,
                   "slices per light-view column (32 per word; 1024 per geometry pass of 8 "
                   "RGBA32UI targets and per material class)",
                   "[Eisemann06 sec. 2, 3]");
    schema.boolean("local_slicing", true,
                   "slices subdivide each column's [near, far] of the transparent casters (one "
                   "MIN-blended range pass per view) instead of the whole light view",
                   "[Eisemann06 sec. 2.2]");
    schema.choice(
        "method", "raster", {"raster", "conservative", "three-axis", "compute"},
        "voxelizer method (src/voxelize names): raster = one slice per texel centre per "
        "surface ([Eisemann06], exact counts for thin surfaces); conservative = every slice of "
        "the surface's depth range over the texel (steep surfaces count more than "
        "once); three-axis and compute need CPU triangles in a world grid: an error",
        "[Eisemann06 sec. 2]");
    schema.integer("classes", 3, 1, 3,
                   "material classes (maps per view): casters are grouped by their transmittance "
                   "per crossing surface 1 - alpha + alpha T; each class has its own T_c",
                   "[Eisemann06 sec. 3] (three leaf colours)");
    addFogDepthProperties(schema, false);
    registry.add(
        {"transmittance-slicemap",
         "[Eisemann06] transmittance shadow maps: light-space slice maps of the semi-transparent "
         "casters per material class, attenuation prod T_c^(n_c) from slice counts, "
         "times the opaque casters' map",
         nullptr,
         [](gpu::ProgramManager& programs, const Properties& p) {
             return std::make_unique<TransmittanceSlicemapTechnique>(programs, p);
         },
         std::move(schema)});
}

} // namespace veil::shadows
