#include "shadows/moment/moment.h"

#include "shadows/common/depth_maps.h"
#include "shadows/opaque/opaque.h"

#include <fmt/format.h>

#include <algorithm>

namespace veil::shadows {

namespace {

gpu::Texture makeArray(GLenum format, int size, int layers) {
    gpu::Texture t(GL_TEXTURE_2D_ARRAY);
    t.storage3D(1, format, size, size, layers)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return t;
}

class MomentTechnique final : public Technique {
public:
    MomentTechnique(gpu::ProgramManager& programs, const Properties& p)
        : programs_(programs), depth_(programs), bias_(p.getFloat("bias")),
          pcfRadius_(p.getInt("pcf_radius")), momentBias_(p.getFloat("moment_bias")),
          overestimation_(p.getFloat("overestimation")),
          mediaOverestimation_(p.getFloat("media_overestimation")),
          quantized_(p.getString("storage") == "quantized16"), blurRadius_(p.getInt("blur_radius")),
          mediaSteps_(p.getInt("media_steps")), mediaSkipEmpty_(p.getBool("media_skip_empty")),
          receiverOffset_(p.getFloat("receiver_offset")) {
        using gpu::ProgramDesc;
        caster_ =
            programs.add(ProgramDesc::graphics("frame/mesh.vert", "shadows/moment/caster.frag"));
        mediaProgram_ = programs.add(ProgramDesc::compute("shadows/moment/media.comp"));
        blur_ = programs.add(ProgramDesc::compute("shadows/moment/blur.comp"));
        quantize_ = programs.add(ProgramDesc::compute("shadows/moment/quantize.comp"));
        clear_ = programs.add(ProgramDesc::compute("shadows/moment/clear.comp"));
    }

    std::string name() const override { return "moment"; }
    std::filesystem::path visibilityInclude() const override {
        return "shadows/moment/visibility.glsl";
    }

    void resize(int mapSize, int viewCount) override {
        depth_.resize(mapSize, viewCount);
        if (mapSize == size_ && viewCount == layers_) return;
        size_ = mapSize;
        layers_ = viewCount;
        absorbance_ = makeArray(GL_RGBA32F, size_, layers_);
        moments_ = makeArray(GL_RGBA32F, size_, layers_);
        media_ = makeArray(GL_RGBA32F, size_, layers_);
        temp_ = makeArray(GL_RGBA32F, size_, layers_);
        if (quantized_) {
            absorbance16_ = makeArray(GL_RGBA16F, size_, layers_);
            moments16_ = makeArray(GL_RGBA16, size_, layers_);
            media16_ = makeArray(GL_RGBA16, size_, layers_);
        }
        framebuffer_ = gpu::Framebuffer();
        for (gpu::Texture& t : bandTemps_)
            t = gpu::Texture(gpu::NoCreate);
    }

    // Every pass also runs in bands of texel rows (pass::Pass::executeRows): each texel of
    // the depth, caster, media and quantize passes depends on its own texel only, so a band
    // is the whole pass with its clears, draws (scissor) and dispatches restricted to the
    // rows; the filter's bands are filterRows().
    std::vector<pass::Pass> passes() override {
        std::vector<pass::Pass> p;
        p.push_back(
            {"",
             {},
             {"shadow.depth"},
             [this](const pass::Context& f) { depth_.render(f); },
             [this](const pass::Context& f, int y0, int y1) { depth_.renderRows(f, y0, y1); }});
        p.push_back({"transparent",
                     {},
                     {"shadow.moments"},
                     [this](const pass::Context& f) { renderCasters(f, 0, size_); },
                     [this](const pass::Context& f, int y0, int y1) { renderCasters(f, y0, y1); }});
        p.push_back({"media",
                     {"shadow.moments"},
                     {"shadow.moments"},
                     [this](const pass::Context& f) { renderMedia(f, 0, size_); },
                     [this](const pass::Context& f, int y0, int y1) { renderMedia(f, y0, y1); }});
        if (blurRadius_ > 0)
            p.push_back({"filter",
                         {"shadow.moments"},
                         {"shadow.moments"},
                         [this](const pass::Context&) { filter(); },
                         [this](const pass::Context&, int y0, int y1) { filterRows(y0, y1); }});
        if (quantized_)
            p.push_back({"quantize",
                         {"shadow.moments"},
                         {"shadow.moments16"},
                         [this](const pass::Context&) { quantize(0, size_); },
                         [this](const pass::Context&, int y0, int y1) { quantize(y0, y1); }});
        return p;
    }
    std::vector<std::string> receiverResources() const override {
        return {"shadow.depth", quantized_ ? "shadow.moments16" : "shadow.moments"};
    }
    void bindForReceivers() const override {
        depth_.bind();
        (quantized_ ? absorbance16_ : absorbance_).bind(VEIL_TEX_SHADOW1);
        (quantized_ ? moments16_ : moments_).bind(VEIL_TEX_SHADOW2);
        (quantized_ ? media16_ : media_).bind(VEIL_TEX_SHADOW3);
    }
    void fillParams(ShadowsBlock& block) const override {
        block.params[0] =
            glm::vec4(bias_, static_cast<float>(pcfRadius_), mediaOverestimation_, 0.0f);
        block.params[1] =
            glm::vec4(momentBias_, overestimation_, quantized_ ? 1.0f : 0.0f, receiverOffset_);
    }
    bool attenuatesMedia() const override { return true; }
    const gpu::Texture* resourceTexture(const std::string& name) const override {
        if (name == "shadow.depth") return &depth_.texture();
        if (name == "shadow.moments") return &moments_;
        if (name == "shadow.moments16" && quantized_) return &moments16_;
        return nullptr;
    }
    // Depth, moments of the transparent casters and of the media, filtered and quantized,
    // all from the light views: no camera.
    bool dependsOnCamera() const override { return false; }
    std::size_t gpuBytes() const override {
        const std::size_t texels = std::size_t(size_) * size_ * layers_;
        const int bandTemps = bandTemps_[0] ? 2 : 0; // filterRows() made them
        return depth_.gpuBytes() + texels * ((4 + bandTemps) * 16 + (quantized_ ? 3 * 8 : 0));
    }
    nlohmann::json stats() const override {
        return {{"bytes_per_texel_read", quantized_ ? 24 : 48}, {"media_marched", mediaMarched_}};
    }

private:
    // Texel rows [y0, y1) of every layer, 8 x 8 groups; the program's `rows` uniform says
    // which (the shaders offset gl_GlobalInvocationID.y by rows.x and stop at rows.y).
    void dispatchRows(const gpu::Program& program, int y0, int y1) const {
        program.set("rows", glm::ivec2(y0, y1));
        glDispatchCompute(static_cast<GLuint>((size_ + 7) / 8),
                          static_cast<GLuint>((y1 - y0 + 7) / 8), static_cast<GLuint>(layers_));
    }

    // Rows [y0, y1): the clear and the additive draws (scissor) of those rows. Blending adds
    // a texel's fragments in primitive order whatever the scissor box, so the bands sum to
    // the whole pass's values exactly.
    void renderCasters(const pass::Context& f, int y0, int y1) {
        const gpu::Program& program = programs_.get(caster_);
        gpu::PipelineState s;
        s.view(size_, size_);
        s.depthTest = false; // [Munstermann18 sec. 6]: no depth test against the opaque casters
        s.depthWrite = false;
        s.blendAll(gpu::BlendState::func(GL_ONE, GL_ONE));
        if (y0 > 0 || y1 < size_) {
            s.scissorTest = true;
            s.scissor = glm::ivec4(0, y0, size_, y1 - y0);
        }
        clearMaps(y0, y1);
        for (const LightView& view : *f.lightViews) {
            framebuffer_.attachLayer(GL_COLOR_ATTACHMENT0, absorbance_, view.layer)
                .attachLayer(GL_COLOR_ATTACHMENT1, moments_, view.layer)
                .attachLayer(GL_COLOR_ATTACHMENT2, media_, view.layer)
                .drawBuffers({GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2});
            framebuffer_.bind();
            f.state->apply(s);
            program.use();
            setCasterView(program, view);
            program.set("shadowView", view.layer);
            f.drawObjects(program, pass::ObjectSet::TransparentCasters);
        }
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

    // Rows [y0, y1) of every layer of the three arrays to zero by compute
    // (shaders/shadows/moment/clear.comp says why not the framebuffer clear), visible to the
    // blending that follows.
    void clearMaps(int y0, int y1) {
        const gpu::Program& program = programs_.get(clear_);
        program.use();
        glBindImageTexture(1, absorbance_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glBindImageTexture(2, moments_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glBindImageTexture(3, media_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        dispatchRows(program, y0, y1);
        glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                        GL_TEXTURE_FETCH_BARRIER_BIT);
    }

    void renderMedia(const pass::Context& f, int y0, int y1) {
        mediaMarched_ = static_cast<bool>(f.bindMedia);
        if (!f.bindMedia) return;
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
        const gpu::Program& program = programs_.get(mediaProgram_);
        f.bindMedia(program);
        for (const LightView& view : *f.lightViews)
            program.set(fmt::format("clipToWorld[{}]", view.layer).c_str(),
                        glm::inverse(view.viewProjection));
        program.set("firstLayer", 0)
            .set("steps", mediaSteps_)
            .set("skipEmptyLeaves", mediaSkipEmpty_ ? 1 : 0);
        program.use();
        glBindImageTexture(1, absorbance_.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA32F);
        glBindImageTexture(2, media_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        dispatchRows(program, y0, y1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }

    // One direction of the separable Gaussian (blur.comp) from `source` into rows [y0, y1) of
    // `target`.
    void blurRows(const gpu::Texture& source, const gpu::Texture& target, glm::ivec2 direction,
                  int y0, int y1) const {
        const gpu::Program& program = programs_.get(blur_);
        program.use();
        program.set("radius", blurRadius_).set("direction", direction);
        source.bind(VEIL_TEX_SHADOW1);
        glBindImageTexture(1, target.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        dispatchRows(program, y0, y1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }

    // [Munstermann18 sec. 6]'s Gaussian, separable: each map horizontally into temp_, vertically
    // back.
    void filter() {
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
        for (gpu::Texture* t : {&absorbance_, &moments_, &media_}) {
            blurRows(*t, temp_, {1, 0}, 0, size_);
            blurRows(temp_, *t, {0, 1}, 0, size_);
        }
    }

    // filter() over rows [y0, y1) of each map, the bands in order (pass::Pass::executeRows).
    // The vertical blur of rows [y0, y1) reads the horizontal result of rows [y0 - r, y1 + r)
    // and writes the map in place, so each map keeps its own horizontal result across the
    // bands (bandTemps_, made on first use: two more arrays than filter() needs) and every
    // band blurs horizontally only the rows no earlier band did, [y0 + r, y1 + r): the map's
    // rows from y0 + r on are not yet overwritten by the vertical blurs (those wrote rows
    // < y0). Each texel then sums the same taps in the same order as filter(): bit for bit.
    void filterRows(int y0, int y1) {
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
        if (!bandTemps_[0]) {
            bandTemps_[0] = makeArray(GL_RGBA32F, size_, layers_);
            bandTemps_[1] = makeArray(GL_RGBA32F, size_, layers_);
        }
        const gpu::Texture* temps[3] = {&temp_, &bandTemps_[0], &bandTemps_[1]};
        gpu::Texture* maps[3] = {&absorbance_, &moments_, &media_};
        const int h0 = y0 == 0 ? 0 : std::min(y0 + blurRadius_, size_);
        const int h1 = std::min(y1 + blurRadius_, size_);
        for (int i = 0; i < 3; ++i) {
            if (h0 < h1) blurRows(*maps[i], *temps[i], {1, 0}, h0, h1);
            blurRows(*temps[i], *maps[i], {0, 1}, y0, y1);
        }
    }

    void quantize(int y0, int y1) {
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
        const gpu::Program& program = programs_.get(quantize_);
        program.use();
        absorbance_.bind(VEIL_TEX_SHADOW1);
        moments_.bind(VEIL_TEX_SHADOW2);
        media_.bind(VEIL_TEX_SHADOW3);
        glBindImageTexture(1, absorbance16_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        glBindImageTexture(2, moments16_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16);
        glBindImageTexture(3, media16_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16);
        dispatchRows(program, y0, y1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    }

    gpu::ProgramManager& programs_;
    DepthMaps depth_;
    float bias_;
    int pcfRadius_;
    float momentBias_, overestimation_, mediaOverestimation_;
    bool quantized_;
    int blurRadius_, mediaSteps_;
    bool mediaSkipEmpty_;
    float receiverOffset_;
    gpu::ProgramHandle caster_, mediaProgram_, blur_, quantize_, clear_;
    int size_ = 0, layers_ = 0;
    // absorbance_: surfaces' b0 per channel, media b0 in alpha; moments_: the surfaces' mean
    // absorbance moments; media_: the media's moments.
    gpu::Texture absorbance_{gpu::NoCreate}, moments_{gpu::NoCreate}, media_{gpu::NoCreate};
    gpu::Texture temp_{gpu::NoCreate};
    gpu::Texture bandTemps_[2]{gpu::Texture(gpu::NoCreate), gpu::Texture(gpu::NoCreate)};
    gpu::Texture absorbance16_{gpu::NoCreate}, moments16_{gpu::NoCreate}, media16_{gpu::NoCreate};
    gpu::Framebuffer framebuffer_{gpu::NoCreate};
    bool mediaMarched_ = false;
};

} // namespace

void registerMoment(Registry& registry) {
    PropertySchema schema = commonProperties();
    addOpaqueMapProperties(schema);
    schema
        .real("moment_bias", 6e-5, 0.0, 0.1,
              "bias alpha toward the power-4 bias vector (docs/oit.md#moment-constants)",
              "[Munstermann18 sec. 3.2]")
        .real("overestimation", 0.0, 0.0, 1.0,
              "overestimation weight beta of the surfaces' moments; 0 for shadows "
              "[Munstermann18 sec. 7.2]",
              "[Munstermann18 Algorithm 2]")
        .real("media_overestimation", 0.25, 0.0, 1.0,
              "overestimation weight beta of the density volumes' own moments: a continuous "
              "absorbance, where beta = 0 (the lower bound) makes the smoke's self-shadowing "
              "light (fog.json's smoke alone vs the CPU reference: RMSE 1.54x reference's at 0, "
              "1.13x at 0.25)",
              "[Munstermann18 sec. 3.2, Algorithm 2]")
        .choice("storage", "float32", {"float32", "quantized16"},
                "moment storage the receivers read: float32, or 16-bit quantized after "
                "filtering (half-float b0, UNORM16 normalized moments)",
                "[Munstermann18 sec. 4.1, 6]")
        .integer("blur_radius", 4, 0, 32,
                 "separable Gaussian taps each side (sigma = r/2); 4 = [Munstermann18]'s 9x9",
                 "[Munstermann18 sec. 6]")
        .integer("media_steps", 64, 1, 4096,
                 "steps per texel ray through the volumes' bounds (density absorbance)")
        .boolean("media_skip_empty", true,
                 "jump over the steps in leaves empty in every volume (the same sums, fewer "
                 "samples); off visits every step")
        .real("receiver_offset", 0.02, 0.0, 1e6,
              "world distance toward the light at which receivers read the moments (a "
              "transparent receiver does not shadow itself)");
    registry.add({"moment",
                  "absorbance moment shadow maps of transparent casters and density volumes "
                  "(4 power moments, colour by per-channel b0), opaque casters by PCF",
                  nullptr,
                  [](gpu::ProgramManager& programs, const Properties& p) {
                      return std::make_unique<MomentTechnique>(programs, p);
                  },
                  std::move(schema)});
}

} // namespace veil::shadows
