// `stochastic` [Enderton11] and `stochastic-vsm` [McGuire16] shadow techniques: see stochastic.h.
//
// Resources:
//   shadow.depth       the opaque casters' Williams maps (DepthMaps), both techniques
//   shadow.stochastic  `stochastic`: DEPTH32F MSAA array, S samples, L layers per view (L = 3
//                      when `colored`, channel c of view v at layer v L + c), the receivers'
//                      map
//   shadow.moments     `stochastic-vsm`: RG32F array (z, z^2 averaged over each texel's S
//                      samples), same layer layout; the MSAA map is then only an intermediate
//                      of L layers reused for every view
//   shadow.vsm         `stochastic-vsm`: shadow.moments after the separable tent blur (the
//                      receivers' map, bilinear)
//   shadow.fog         both, with `fog`: the grid density volumes' optical depth along the
//                      light views (FogDepthMap), times the surfaces' stochastic visibility
#include "shadows/stochastic/stochastic.h"

#include "base/error.h"
#include "shaders/common/bindings.h"
#include "shadows/common/depth_maps.h"
#include "shadows/common/fog_depth.h"
#include "shadows/opaque/opaque.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace veil::shadows {

namespace {

enum class Mode { Stochastic, Vsm };

int effectiveSamples(int requested) {
    GLint maxSamples = 0, maxDepth = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    glGetIntegerv(GL_MAX_DEPTH_TEXTURE_SAMPLES, &maxDepth);
    const int limit = std::min({static_cast<int>(maxSamples), static_cast<int>(maxDepth), 32});
    VEIL_CHECK(limit >= 1, "stochastic shadows: the GL driver reports no MSAA support");
    return std::clamp(requested, 1, limit);
}

class StochasticShadows final : public Technique {
public:
    StochasticShadows(Mode mode, gpu::ProgramManager& programs, const Properties& p)
        : mode_(mode), programs_(programs), depth_(programs), bias_(p.getFloat("bias")),
          pcfRadius_(p.getInt("pcf_radius")), samples_(effectiveSamples(p.getInt("samples"))),
          channels_(p.getBool("colored") ? 3 : 1) {
        using gpu::ProgramDesc;
        if (p.getBool("fog"))
            fogMap_.emplace(programs, p.getInt("fog_columns"), p.getInt("fog_slices"),
                            p.getInt("fog_substeps"));
        casterProgram_ = programs.add(
            ProgramDesc::graphics("frame/mesh.vert", "shadows/stochastic/caster.frag"));
        if (mode_ == Mode::Stochastic) {
            filterRadius_ = p.getInt("filter_radius");
        } else {
            caustics_ = p.getBool("caustics");
            blurRadius_ = p.getInt("blur_radius");
            lightBleeding_ = p.getFloat("light_bleeding");
            fogReadsVsm_ = p.getBool("fog_reads_vsm");
            opaqueProgram_ =
                programs.add(ProgramDesc::graphics("frame/mesh.vert", "shadows/common/depth.frag"));
            momentsProgram_ = programs.add(ProgramDesc::compute("shadows/stochastic/moments.comp"));
            blurProgram_ = programs.add(ProgramDesc::compute("shadows/stochastic/blur.comp"));
        }
    }

    std::string name() const override {
        return mode_ == Mode::Stochastic ? "stochastic" : "stochastic-vsm";
    }
    std::filesystem::path visibilityInclude() const override {
        return mode_ == Mode::Stochastic ? "shadows/stochastic/visibility.glsl"
                                         : "shadows/stochastic/vsm_visibility.glsl";
    }

    void resize(int mapSize, int viewCount) override {
        depth_.resize(mapSize, viewCount);
        if (fogMap_) fogMap_->resize(mapSize, viewCount);
        if (mapSize == size_ && viewCount == views_) return;
        size_ = mapSize;
        views_ = viewCount;
        const int layers = std::max(viewCount, 1) * channels_;
        // `stochastic` keeps every view's MSAA map for the receivers; `stochastic-vsm` only
        // needs one view's at a time.
        const int msLayers = mode_ == Mode::Stochastic ? layers : channels_;
        msDepth_ = gpu::Texture(GL_TEXTURE_2D_MULTISAMPLE_ARRAY);
        glTextureStorage3DMultisample(msDepth_.id(), samples_, GL_DEPTH_COMPONENT32F, size_, size_,
                                      msLayers, GL_TRUE);
        msLayers_ = msLayers;
        framebuffer_ = gpu::Framebuffer();
        if (mode_ == Mode::Vsm) {
            auto moments = [&](GLenum filter) {
                gpu::Texture t(GL_TEXTURE_2D_ARRAY);
                t.storage3D(1, GL_RG32F, size_, size_, layers)
                    .parameter(GL_TEXTURE_MIN_FILTER, static_cast<GLint>(filter))
                    .parameter(GL_TEXTURE_MAG_FILTER, static_cast<GLint>(filter))
                    .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
                    .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
                return t;
            };
            moments_ = moments(GL_NEAREST);
            blurTmp_ = moments(GL_NEAREST);
            vsm_ = moments(GL_LINEAR);
        }
    }

    // Every pass also runs in bands of texel rows (pass::Pass::executeRows): a texel's
    // samples depend on its own fragments only (the masks hash the texel and the depth, not
    // the viewport), and its moments on its own samples, so those bands are the pass with
    // its clears and draws scissored and its dispatch restricted to the rows; the blur's
    // bands are blur().
    std::vector<pass::Pass> passes() override {
        std::vector<pass::Pass> p;
        p.push_back(
            {"",
             {},
             {"shadow.depth"},
             [this](const pass::Context& f) { depth_.render(f); },
             [this](const pass::Context& f, int y0, int y1) { depth_.renderRows(f, y0, y1); }});
        auto stochastic = [this](const pass::Context& f) { renderStochastic(f, 0, size_); };
        auto stochasticRows = [this](const pass::Context& f, int y0, int y1) {
            renderStochastic(f, y0, y1);
        };
        if (mode_ == Mode::Stochastic) {
            p.push_back({"stochastic", {}, {"shadow.stochastic"}, stochastic, stochasticRows});
        } else {
            p.push_back({"stochastic", {}, {"shadow.moments"}, stochastic, stochasticRows});
            p.push_back({"vsm",
                         {"shadow.moments"},
                         {"shadow.vsm"},
                         [this](const pass::Context& f) { blur(f, 0, size_); },
                         [this](const pass::Context& f, int y0, int y1) { blur(f, y0, y1); }});
        }
        if (fogMap_) p.push_back(fogMap_->pass());
        return p;
    }
    std::vector<std::string> receiverResources() const override {
        std::vector<std::string> r = {
            "shadow.depth", mode_ == Mode::Stochastic ? "shadow.stochastic" : "shadow.vsm"};
        if (fogMap_) r.push_back("shadow.fog");
        return r;
    }
    // With `fog`, the fog samples read the media's optical depth from the fog map, so the
    // marcher's own self-shadowing is off.
    bool attenuatesMedia() const override { return fogMap_.has_value(); }
    void bindForReceivers() const override {
        depth_.bind();
        (mode_ == Mode::Stochastic ? msDepth_ : vsm_).bind(VEIL_TEX_SHADOW1);
        if (fogMap_) fogMap_->bind();
    }
    void prepareReceiver(const gpu::Program& program, const pass::Context&) const override {
        if (fogMap_)
            fogMap_->prepareReceiver(program);
        else
            program.set("shadowFog", 0);
    }
    WorkEstimate work(int, int viewCount, bool media) const override {
        return fogMap_ ? fogMap_->work(viewCount, media) : WorkEstimate{};
    }
    void fillParams(ShadowsBlock& block) const override {
        block.params[0] = glm::vec4(bias_, static_cast<float>(pcfRadius_), 0.0f, 0.0f);
        if (mode_ == Mode::Stochastic)
            block.params[1] =
                glm::vec4(static_cast<float>(samples_), static_cast<float>(filterRadius_),
                          static_cast<float>(channels_), 0.0f);
        else
            block.params[1] = glm::vec4(lightBleeding_, static_cast<float>(channels_), 0.0f, 0.0f);
    }
    const gpu::Texture* resourceTexture(const std::string& name) const override {
        if (name == "shadow.depth") return &depth_.texture();
        if (name == "shadow.fog") return fogMap_ ? &fogMap_->texture() : nullptr;
        if (mode_ == Mode::Stochastic) return name == "shadow.stochastic" ? &msDepth_ : nullptr;
        if (name == "shadow.moments") return &moments_;
        if (name == "shadow.vsm") return &vsm_;
        return nullptr;
    }
    // The casters' stochastic samples from the light views with the scene's fixed seed
    // (render.seed, not a frame counter): no camera.
    bool dependsOnCamera() const override { return false; }
    std::size_t gpuBytes() const override {
        const std::size_t texels = std::size_t(size_) * size_;
        std::size_t bytes = depth_.gpuBytes() + texels * samples_ * 4 * msLayers_;
        if (mode_ == Mode::Vsm) bytes += 3 * texels * 8 * std::max(views_, 1) * channels_;
        return bytes + (fogMap_ ? fogMap_->gpuBytes() : 0);
    }
    nlohmann::json stats() const override {
        nlohmann::json s = {{"effective_samples", samples_}, {"layers_per_view", channels_}};
        if (mode_ == Mode::Vsm) s["blur_texels"] = stochasticVsmBlurTexels(blurRadius_, size_);
        return s;
    }

private:
    // [Enderton11 sec. 3.2 / 3.6]: per view and channel, a stratified stochastic MSAA depth map of
    // the transparent casters. VSM: the opaque casters first, so that a sample no transparent
    // surface covers holds the depth of what is behind (the receiver's own depth where it is
    // the first opaque surface), which makes Chebyshev's bound exact for one plane.
    // Rows [y0, y1) of every layer (all of them: 0, size_).
    void renderStochastic(const pass::Context& frame, int y0, int y1) {
        const gpu::Program& caster = programs_.get(casterProgram_);
        for (const LightView& view : *frame.lightViews) {
            for (int c = 0; c < channels_; ++c) {
                const int layer = mode_ == Mode::Stochastic ? view.layer * channels_ + c : c;
                framebuffer_.attachLayer(GL_DEPTH_ATTACHMENT, msDepth_, layer)
                    .drawBuffers({GL_NONE});
                framebuffer_.bind();
                gpu::PipelineState s;
                s.view(size_, size_).depth(GL_LESS, true); // multisample on (default)
                if (y0 > 0 || y1 < size_) { // a band: the clear and the draws in its rows
                    s.scissorTest = true;
                    s.scissor = glm::ivec4(0, y0, size_, y1 - y0);
                }
                frame.state->apply(s); // before the clear: depth mask
                const float one = 1.0f;
                glClearNamedFramebufferfv(framebuffer_.id(), GL_DEPTH, 0, &one);
                if (mode_ == Mode::Vsm) {
                    const gpu::Program& opaque = programs_.get(opaqueProgram_);
                    opaque.use();
                    setCasterView(opaque, view);
                    opaque.set("shadowView", view.layer);
                    frame.drawObjects(opaque, pass::ObjectSet::OpaqueCasters);
                }
                caster.use();
                setCasterView(caster, view);
                caster.set("shadowView", view.layer)
                    .set("stochSeed", static_cast<unsigned>(frame.seed))
                    .set("stochSamples", samples_)
                    .set("stochChannel", channels_ == 3 ? c : -1)
                    .set("caustics", mode_ == Mode::Vsm && caustics_ ? 1 : 0)
                    .set("lightOrthographic", view.orthographic ? 1 : 0)
                    .set("lightPosition", view.position)
                    .set("lightDirection", view.direction);
                frame.drawObjects(caster, pass::ObjectSet::TransparentCasters);
            }
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            if (mode_ == Mode::Vsm) resolveMoments(frame, view, y0, y1);
        }
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

    // [McGuire16 sec. 4.3]: "convert the shadow maps to Variance Shadow Maps": per texel the mean
    // of z and z^2 over its S samples (the box filter of the samples, [Enderton11 sec. 4.1]
    // operator F).
    void resolveMoments(const pass::Context& frame, const LightView& view, int y0, int y1) {
        frame.state->apply(gpu::PipelineState{}); // compute only
        const gpu::Program& program = programs_.get(momentsProgram_);
        program.use();
        program.set("samples", samples_).set("firstLayer", view.layer * channels_);
        msDepth_.bind(VEIL_TEX_SHADOW3);
        glBindImageTexture(VEIL_IMG_OUTPUT, moments_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RG32F);
        glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
        dispatchRows(program, y0, y1, channels_);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    }

    // [McGuire16 sec. 4.3]: "filter them with a 15x15 tent kernel (in two 1D passes)", here for the
    // rows [y0, y1) of vsm_ (all of them: 0, size_). The vertical pass of those rows reads
    // the horizontal result (blurTmp_) of rows [y0 - r, y1 + r); bands run in order, so an
    // earlier band made it up to row y0 + r and this one adds rows [y0 + r, y1 + r) (from
    // moments_, which this pass does not change): every texel the same sums as in one piece.
    void blur(const pass::Context& frame, int y0, int y1) {
        frame.state->apply(gpu::PipelineState{}); // compute only
        const gpu::Program& program = programs_.get(blurProgram_);
        program.use();
        const int layers = std::max(views_, 1) * channels_;
        const int radius = stochasticVsmBlurTexels(blurRadius_, size_);
        const gpu::Texture* from[2] = {&moments_, &blurTmp_};
        const gpu::Texture* to[2] = {&blurTmp_, &vsm_};
        const int rows[2][2] = {
            {y0 == 0 ? 0 : std::min(y0 + radius, size_), std::min(y1 + radius, size_)}, {y0, y1}};
        for (int pass = 0; pass < 2; ++pass) {
            if (rows[pass][0] >= rows[pass][1]) continue;
            program.set("radius", radius)
                .set("direction", pass == 0 ? glm::ivec2(1, 0) : glm::ivec2(0, 1));
            from[pass]->bind(VEIL_TEX_SHADOW2);
            glBindImageTexture(VEIL_IMG_OUTPUT, to[pass]->id(), 0, GL_TRUE, 0, GL_WRITE_ONLY,
                               GL_RG32F);
            dispatchRows(program, rows[pass][0], rows[pass][1], layers);
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
        }
    }

    // Texel rows [y0, y1) of `layers` layers; the shader's `rows` uniform says which.
    void dispatchRows(const gpu::Program& program, int y0, int y1, int layers) const {
        program.set("rows", glm::ivec2(y0, y1));
        glDispatchCompute(static_cast<GLuint>((size_ + 7) / 8),
                          static_cast<GLuint>((y1 - y0 + 7) / 8), static_cast<GLuint>(layers));
    }

    Mode mode_;
    gpu::ProgramManager& programs_;
    DepthMaps depth_;
    float bias_;
    int pcfRadius_;
    int samples_;
    int channels_;
    int filterRadius_ = 0;
    bool caustics_ = false;
    int blurRadius_ = 0;
    float lightBleeding_ = 0.0f;
    bool fogReadsVsm_ = false;
    gpu::ProgramHandle casterProgram_, opaqueProgram_, momentsProgram_, blurProgram_;
    gpu::Texture msDepth_{gpu::NoCreate};
    gpu::Texture moments_{gpu::NoCreate}, blurTmp_{gpu::NoCreate}, vsm_{gpu::NoCreate};
    gpu::Framebuffer framebuffer_{gpu::NoCreate};
    std::optional<FogDepthMap> fogMap_;
    int size_ = 0, views_ = 0, msLayers_ = 0;
};

PropertySchema& addStochasticProperties(PropertySchema& s) {
    s.integer("samples", 8, 1, 32,
              "MSAA samples S of the stochastic map per texel and channel (clamped to "
              "GL_MAX_SAMPLES and GL_MAX_DEPTH_TEXTURE_SAMPLES; llvmpipe has 4)",
              "[Enderton11 sec. 3.5, 3.6]");
    s.boolean("colored", true,
              "one stochastic map per RGB channel with rho = alpha (1 - t) per channel (colored "
              "stochastic shadow maps); false: one map of the channels' mean rho (grey)",
              "[McGuire16 sec. 4.3]");
    return s;
}

void add(Registry& registry, const char* id, Mode mode, const char* description) {
    PropertySchema schema = commonProperties(); // 2048: the opaque map shares the size
    addOpaqueMapProperties(schema);
    addStochasticProperties(schema);
    addFogDepthProperties(schema, true);
    if (mode == Mode::Stochastic) {
        schema.integer("filter_radius", 2, 0, 8,
                       "PCF of the stochastic map over (2r+1)^2 texels x S samples (surfaces; "
                       "volume samples read one texel)",
                       "[Enderton11 sec. 3.2, Eq. 4, sec. 3.6]");
    } else {
        schema
            .boolean("caustics", false,
                     "caustic density: rho scaled by 1 + g s^0.2 from the incidence and ior "
                     "(off: a flat pane focuses nothing, and the model darkens it at oblique "
                     "incidence, e.g. rho x 1.66 for glass at 45 degrees)",
                     "[McGuire16 sec. 4.3, Eq. 10-12]")
            .integer("blur_radius", 5, 0, 64,
                     "tent blur radius in texels of a 2048^2 map (G3D's default 5), scaled "
                     "by size / 2048 and rounded for other sizes",
                     "[McGuire16 sec. 4.3]")
            .real("light_bleeding", 0.0, 0.0, 0.99,
                  "light-bleeding reduction: visibility = linstep(amount, 1, Chebyshev bound)",
                  "[McGuire16 sec. 4.3] (VSM, [Donnelly06])")
            .boolean("fog_reads_vsm", false,
                     "fog samples (the compute marcher) also read the VSM; off: they get the "
                     "opaque map only, because on llvmpipe (Mesa 23, LLVM 15) the marcher's "
                     "fetches of the RG32F array return zeros in most invocations, which "
                     "blacks out lit fog in vertical streaks (docs/shadows.md)");
    }
    registry.add({id, description, [](const gpu::ContextInfo& c) { return c.maxSamples >= 1; },
                  [mode](gpu::ProgramManager& programs, const Properties& p) {
                      return std::make_unique<StochasticShadows>(mode, programs, p);
                  },
                  std::move(schema)});
}

} // namespace

int stochasticVsmBlurTexels(int blurRadius, int size) {
    return static_cast<int>(std::lround(static_cast<double>(blurRadius) * size / 2048.0));
}

void registerStochastic(Registry& registry) {
    add(registry, "stochastic", Mode::Stochastic,
        "stochastic shadow maps of the transparent casters (MSAA, stratified sample masks, one "
        "map per channel) read by PCF, with the opaque Williams map [Enderton11], times the "
        "density volumes' optical depth along the light views (`fog`)");
    add(registry, "stochastic-vsm", Mode::Vsm,
        "caustic colored stochastic shadow maps converted to blurred variance shadow maps, "
        "Chebyshev bound, with the opaque Williams map [McGuire16], times the density volumes' "
        "optical depth along the light views (`fog`)");
}

} // namespace veil::shadows
