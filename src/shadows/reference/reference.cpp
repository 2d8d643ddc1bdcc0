#include "shadows/reference/reference.h"

#include "base/error.h"
#include "base/log.h"
#include "shadows/common/depth_maps.h"
#include "shadows/opaque/opaque.h"

#include <algorithm>

namespace veil::shadows {

namespace {

constexpr std::size_t kNodeBytes = 32; // std430 { vec4; uint; } padded to 32

class ReferenceTechnique final : public Technique {
public:
    ReferenceTechnique(gpu::ProgramManager& programs, const Properties& p)
        : programs_(programs), depth_(programs), bias_(p.getFloat("bias")),
          pcfRadius_(p.getInt("pcf_radius")), mediaSteps_(p.getInt("media_steps")),
          receiverOffset_(p.getFloat("receiver_offset")), maxList_(p.getInt("max_list")),
          capacity_(static_cast<std::uint32_t>(p.getInt("initial_pool"))) {
        caster_ = programs.add(
            gpu::ProgramDesc::graphics("frame/mesh.vert", "shadows/reference/caster.frag"));
        counter_.setStorage(2 * sizeof(std::uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);
        allocatePool();
    }

    std::string name() const override { return "reference"; }
    std::filesystem::path visibilityInclude() const override {
        return "shadows/reference/visibility.glsl";
    }
    void resize(int mapSize, int viewCount) override {
        depth_.resize(mapSize, viewCount);
        if (mapSize == size_ && viewCount == layers_) return;
        size_ = mapSize;
        layers_ = viewCount;
        heads_ = gpu::Texture(GL_TEXTURE_2D_ARRAY);
        heads_.storage3D(1, GL_R32UI, size_, size_, layers_)
            .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        framebuffer_ = gpu::Framebuffer();
    }
    std::vector<pass::Pass> passes() override {
        // The depth pass also in bands of texel rows (pass::Pass::executeRows); the lists run
        // whole (one pool and counter for every texel, regrown and redrawn on overflow).
        return {{"",
                 {},
                 {"shadow.depth"},
                 [this](const pass::Context& f) { depth_.render(f); },
                 [this](const pass::Context& f, int y0, int y1) { depth_.renderRows(f, y0, y1); }},
                {"transparent", {}, {"shadow.lists"}, [this](const pass::Context& f) {
                     renderLists(f);
                 }}};
    }
    std::vector<std::string> receiverResources() const override {
        return {"shadow.depth", "shadow.lists"};
    }
    void bindForReceivers() const override {
        depth_.bind();
        heads_.bind(VEIL_TEX_SHADOW1);
        nodes_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_NODES);
        counter_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_COUNTER);
    }
    void prepareReceiver(const gpu::Program& program, const pass::Context& frame) const override {
        if (frame.bindMedia) frame.bindMedia(program);
    }
    void fillParams(ShadowsBlock& block) const override {
        block.params[0] = glm::vec4(bias_, static_cast<float>(pcfRadius_), 0.0f, 0.0f);
        block.params[1] = glm::vec4(receiverOffset_, static_cast<float>(mediaSteps_),
                                    static_cast<float>(maxList_), 0.0f);
    }
    bool attenuatesMedia() const override { return true; }
    // Mesa's llvmpipe ends all loops of one shader invocation after 65535 iterations in all
    // (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS, one counter per invocation): the march then stops
    // short and lights the receiver, silently. Measured there on the fog slab (one light): the
    // surfaces' march is exact at 8192 steps and stops short at 12288, i.e. up to 8 iterations
    // per step (their programs loop over all four volume slots). The march takes
    // kMarchUnroll midpoint samples per iteration of its loop (visibility.glsl), and the fog
    // marcher's programs declare only the scene's grid volumes, so a fog sample costs
    // media_steps / kMarchUnroll iterations plus kFogPerStep for the remainder loop (up to 7),
    // the volumes' bounds (up to 4) and the marcher's own loops per light and octave. A frame
    // over the limit less 1024 (the lists, PCF, the marcher's own loop) is refused. Other
    // drivers have no such limit.
    void checkReceiverWork(const gpu::ContextInfo& context, int fogSteps, int lights,
                           const std::string& where) const override {
        if (!context.softwareRenderer) return;
        constexpr long long kLimit = 65535, kBudget = kLimit - 1024;
        constexpr long long kMarchUnroll = 8, kFogPerStep = 16;
        const long long surface = 8LL * mediaSteps_ * lights;
        const long long fog = static_cast<long long>(fogSteps) * lights *
                              ((mediaSteps_ + kMarchUnroll - 1) / kMarchUnroll + kFogPerStep);
        VEIL_CHECK(surface <= kBudget && fog <= kBudget,
                   "{}: reference shadows march media_steps = {} toward {} light(s): about {} "
                   "loop iterations per surface and {} per fog pixel ({} fog steps), over the "
                   "{} per shader invocation that {} allows less 1024 (Mesa's loop limit of "
                   "{}: the march would stop short and light the shadow); lower "
                   "render.shadows.media_steps or render.fog_steps",
                   where, mediaSteps_, lights, surface, fog, fogSteps, kBudget, context.renderer,
                   kLimit);
    }
    const gpu::Texture* resourceTexture(const std::string& name) const override {
        if (name == "shadow.depth") return &depth_.texture();
        if (name == "shadow.lists") return &heads_;
        return nullptr;
    }
    // The depth map and the per-texel lists of the transparent casters from the light
    // views: no camera (the media are marched by the receivers).
    bool dependsOnCamera() const override { return false; }
    std::size_t gpuBytes() const override {
        return depth_.gpuBytes() + std::size_t(size_) * size_ * layers_ * 4 +
               std::size_t(capacity_) * kNodeBytes;
    }
    nlohmann::json stats() const override {
        return {{"fragments", fragments_}, {"capacity", capacity_}, {"regrown", regrown_}};
    }

private:
    void allocatePool() {
        nodes_ = gpu::Buffer();
        nodes_.setStorage(std::size_t(capacity_) * kNodeBytes, nullptr, 0);
    }

    void renderLists(const pass::Context& f) {
        const gpu::Program& program = programs_.get(caster_);
        for (int attempt = 0; attempt < 2; ++attempt) {
            const std::uint32_t counter[2] = {0u, capacity_};
            counter_.setSubData(0, sizeof(counter), counter);
            const std::uint32_t empty = 0xFFFFFFFFu;
            glClearTexImage(heads_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &empty);
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            gpu::PipelineState s;
            s.view(size_, size_);
            s.depthTest = false; // every fragment; the opaque casters are the depth map's
            s.depthWrite = false;
            s.colorMask[0] = glm::bvec4(false);
            nodes_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_NODES);
            counter_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_COUNTER);
            glBindImageTexture(1, heads_.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
            for (const LightView& view : *f.lightViews) {
                // The depth layer gives the framebuffer its size; it is neither tested nor written.
                framebuffer_.attachLayer(GL_DEPTH_ATTACHMENT, depth_.texture(), view.layer)
                    .drawBuffers({GL_NONE});
                framebuffer_.bind();
                f.state->apply(s);
                program.use();
                setCasterView(program, view);
                program.set("shadowView", view.layer);
                f.drawObjects(program, pass::ObjectSet::TransparentCasters);
            }
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                            GL_TEXTURE_FETCH_BARRIER_BIT);
            std::uint32_t used = 0;
            glGetNamedBufferSubData(counter_.id(), 0, sizeof(used), &used);
            fragments_ = used;
            if (used <= capacity_) return;
            // Too small: grow to what this frame needed (plus a margin) and redo the pass.
            const std::uint64_t want = std::uint64_t(used) + used / 4 + 1024;
            VEIL_CHECK(want * kNodeBytes <= (std::uint64_t(4) << 30),
                       "shadow reference: {} caster fragments need {:.1f} GiB of lists, over 4 "
                       "GiB (lower render.shadows.size)",
                       used, double(want * kNodeBytes) / double(1 << 30));
            capacity_ = static_cast<std::uint32_t>(want);
            allocatePool();
            ++regrown_;
        }
    }

    gpu::ProgramManager& programs_;
    DepthMaps depth_;
    float bias_;
    int pcfRadius_, mediaSteps_;
    float receiverOffset_;
    int maxList_;
    std::uint32_t capacity_;
    gpu::ProgramHandle caster_;
    int size_ = 0, layers_ = 0;
    gpu::Texture heads_{gpu::NoCreate};
    gpu::Buffer nodes_{gpu::NoCreate};
    gpu::Buffer counter_;
    gpu::Framebuffer framebuffer_{gpu::NoCreate};
    std::uint32_t fragments_ = 0;
    int regrown_ = 0;
};

} // namespace

void registerReference(Registry& registry) {
    PropertySchema schema = commonProperties();
    addOpaqueMapProperties(schema);
    schema.withDefault("pcf_radius", 0);
    schema
        .integer("media_steps", 256, 1, 65536,
                 "midpoint steps of the optical depth from each receiver to the light")
        .real("receiver_offset", 0.02, 0.0, 1e6,
              "world distance toward the light at which receivers read the lists (a "
              "transparent receiver does not shadow itself)")
        .integer("max_list", 4096, 1, 1 << 20, "most fragments read per texel list")
        .integer("initial_pool", 1 << 20, 1024, 1 << 27,
                 "list nodes allocated at first (grown to what a frame needs)");
    registry.add({"reference",
                  "exact visibility at texel resolution: per-texel lists of every transparent "
                  "caster fragment, density marched from each receiver to the light",
                  nullptr,
                  [](gpu::ProgramManager& programs, const Properties& p) {
                      return std::make_unique<ReferenceTechnique>(programs, p);
                  },
                  std::move(schema)});
}

} // namespace veil::shadows
