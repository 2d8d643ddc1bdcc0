#include "oit/phenomenological/phenomenological.h"

#include "base/error.h"

#include "shaders/common/bindings.h"

#include <array>
#include <cmath>
#include <optional>

namespace veil::oit {

void PhenomenologicalParams::validate() const {
    VEIL_CHECK(pixelsPerUnit >= 0.0f && std::isfinite(pixelsPerUnit),
               "phenomenological: pixelsPerUnit must be >= 0 (0 = from the camera), got {}",
               pixelsPerUnit);
    VEIL_CHECK(maxDiffusionPixels >= 1 && maxDiffusionPixels <= 64,
               "phenomenological: maxDiffusionPixels must be in 1..64, got {}", maxDiffusionPixels);
    VEIL_CHECK(k0 >= 0.0f && std::isfinite(k0), "phenomenological: k0 must be >= 0, got {}", k0);
    VEIL_CHECK(k1 > 0.0f && std::isfinite(k1), "phenomenological: k1 must be > 0, got {}", k1);
    VEIL_CHECK(weightMin > 0.0f && weightMin <= weightMax && weightMax <= 1000.0f,
               "phenomenological: need 0 < weightMin <= weightMax <= 1000, got [{}, {}]", weightMin,
               weightMax);
    VEIL_CHECK(particleDownsample == 1 || particleDownsample == 2 || particleDownsample == 4,
               "phenomenological: particleDownsample must be 1, 2 or 4, got {}",
               particleDownsample);
    VEIL_CHECK(refractionDepth > 0.0f && std::isfinite(refractionDepth),
               "phenomenological: refractionDepth must be > 0, got {}", refractionDepth);
    VEIL_CHECK(thicknessReference >= 0.0f && std::isfinite(thicknessReference),
               "phenomenological: thicknessReference must be >= 0 (0 = off), got {}",
               thicknessReference);
    VEIL_CHECK(volumeBlur >= 0.0f && std::isfinite(volumeBlur),
               "phenomenological: volumeBlur must be >= 0, got {}", volumeBlur);
}

nlohmann::json toProperties(const PhenomenologicalParams& p) {
    return {{"pixels_per_unit", p.pixelsPerUnit},
            {"max_diffusion_pixels", p.maxDiffusionPixels},
            {"k0", p.k0},
            {"k1", p.k1},
            {"weight_min", p.weightMin},
            {"weight_max", p.weightMax},
            {"refraction_depth", p.refractionDepth},
            {"self_modulation", p.selfModulation},
            {"refraction", p.refraction},
            {"diffusion", p.diffusion},
            {"particle_downsample", p.particleDownsample},
            {"volume_refraction", p.volumeRefraction},
            {"thickness_reference", p.thicknessReference},
            {"volume_blur", p.volumeBlur},
            {"inferred_ao", p.inferredAO}};
}

PhenomenologicalParams phenomenologicalParams(const Properties& p) {
    PhenomenologicalParams r;
    r.pixelsPerUnit = p.getFloat("pixels_per_unit");
    r.maxDiffusionPixels = p.getInt("max_diffusion_pixels");
    r.k0 = p.getFloat("k0");
    r.k1 = p.getFloat("k1");
    r.weightMin = p.getFloat("weight_min");
    r.weightMax = p.getFloat("weight_max");
    r.refractionDepth = p.getFloat("refraction_depth");
    r.selfModulation = p.getBool("self_modulation");
    r.refraction = p.getBool("refraction");
    r.diffusion = p.getBool("diffusion");
    r.particleDownsample = p.getInt("particle_downsample");
    r.volumeRefraction = p.getBool("volume_refraction");
    r.thicknessReference = p.getFloat("thickness_reference");
    r.volumeBlur = p.getFloat("volume_blur");
    r.inferredAO = p.getBool("inferred_ao");
    return r;
}

namespace {

gpu::Texture makeTarget(GLenum format, int width, int height, GLint filter) {
    gpu::Texture t(GL_TEXTURE_2D);
    t.storage2D(1, format, width, height)
        .parameter(GL_TEXTURE_MIN_FILTER, filter)
        .parameter(GL_TEXTURE_MAG_FILTER, filter)
        .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return t;
}

class PhenomenologicalTechnique final : public Technique {
public:
    // `name`: the registered name it was made under (phenomenological, -nodiff, -volume).
    PhenomenologicalTechnique(gpu::ProgramManager& programs, PhenomenologicalParams params,
                              std::string name)
        : programs_(programs), params_(params), name_(std::move(name)) {
        params_.validate();
        resolveProgram_ =
            programs_.add(gpu::ProgramDesc::compute("oit/phenomenological/resolve.comp"));
        if (params_.volumeRefraction)
            thicknessProgram_ =
                programs_.add(gpu::ProgramDesc::compute("oit/phenomenological/thickness.comp"));
        if (lowRes()) {
            downsampleProgram_ = programs_.add(
                gpu::ProgramDesc::compute("oit/phenomenological/downsample_depth.comp"));
            std::vector<std::string> defines;
            if (params_.refraction) defines.push_back("PHEN_REFRACTION");
            upsampleProgram_ = programs_.add(
                gpu::ProgramDesc::compute("oit/phenomenological/upsample.comp", defines));
        }
    }

    std::string name() const override { return name_; }
    std::filesystem::path emitInclude() const override { return "oit/phenomenological/emit.glsl"; }
    // Reduced-resolution particles: pass 0 draws all but billboards at full resolution,
    // pass 1 only billboards at 1/particleDownsample [McGuire16 sec. 3].
    // Volume refraction adds the slice-map pass in front of them.
    int geometryPasses() const override { return (lowRes() ? 2 : 1) + (volume() ? 1 : 0); }
    std::vector<std::string> defines(int pass) const override {
        if (isThicknessPass(pass)) return {"PHEN_VOLUME", "PHEN_THICKNESS"};
        const int inner = innerPass(pass);
        std::vector<std::string> d;
        if (lowRes()) d.push_back(inner == 0 ? "PHEN_SKIP_BILLBOARDS" : "PHEN_LOWRES");
        if (volume() && inner == 0) d.push_back("PHEN_VOLUME");
        // Without refraction there is no delta target (emit.glsl, upsample.comp).
        if (params_.refraction) d.push_back("PHEN_REFRACTION");
        return d;
    }

    void resize(const pass::Context& targets) override {
        const int w = targets.width, h = targets.height;
        accumA_ = makeTarget(GL_RGBA16F, w, h, GL_NEAREST);
        betaD_ = makeTarget(GL_RGBA16, w, h, GL_NEAREST);
        if (params_.refraction) delta_ = makeTarget(GL_RG16F, w, h, GL_NEAREST);
        depthCopy_ = makeTarget(GL_DEPTH_COMPONENT32F, w, h, GL_NEAREST);
        background_ = makeTarget(GL_RGBA16F, w, h, GL_LINEAR);
        VEIL_CHECK(targets.hdrColor->format() == GL_RGBA16F,
                   "phenomenological: the HDR target must be RGBA16F (copied for the resolve)");
        framebuffer_ = gpu::Framebuffer();
        attachAccumulation(framebuffer_, accumA_, betaD_, delta_);
        framebuffer_.attach(GL_DEPTH_ATTACHMENT, *targets.depth);
        framebuffer_.checkComplete("oit/phenomenological");
        if (volume()) {
            sliceFramebuffer_ = gpu::Framebuffer();
            for (int k = 0; k < 8; ++k) {
                slices_[k] = makeTarget(GL_RGBA32UI, w, h, GL_NEAREST);
                sliceFramebuffer_.attach(GL_COLOR_ATTACHMENT0 + k, slices_[k]);
            }
            sliceFramebuffer_.attach(GL_DEPTH_ATTACHMENT, *targets.depth)
                .drawBuffers({GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                              GL_COLOR_ATTACHMENT3, GL_COLOR_ATTACHMENT4, GL_COLOR_ATTACHMENT5,
                              GL_COLOR_ATTACHMENT6, GL_COLOR_ATTACHMENT7});
            sliceFramebuffer_.checkComplete("oit/phenomenological (slice maps)");
            thickness_ = makeTarget(GL_RG32F, w, h, GL_NEAREST);
        }
        if (lowRes()) {
            const int s = params_.particleDownsample;
            lowWidth_ = (w + s - 1) / s;
            lowHeight_ = (h + s - 1) / s;
            lowA_ = makeTarget(GL_RGBA16F, lowWidth_, lowHeight_, GL_NEAREST);
            lowBetaD_ = makeTarget(GL_RGBA16, lowWidth_, lowHeight_, GL_NEAREST);
            if (params_.refraction)
                lowDelta_ = makeTarget(GL_RG16F, lowWidth_, lowHeight_, GL_NEAREST);
            lowDepth_ = makeTarget(GL_R32F, lowWidth_, lowHeight_, GL_NEAREST);
            lowFramebuffer_ = gpu::Framebuffer();
            attachAccumulation(lowFramebuffer_, lowA_, lowBetaD_, lowDelta_);
            lowFramebuffer_.checkComplete("oit/phenomenological (particles)");
        }
    }

    void beginAccumulate(int pass, const pass::Context& targets,
                         const gpu::Program& program) override {
        if (isThicknessPass(pass)) {
            beginSlicePass(targets);
            return;
        }
        if (volume() && innerPass(pass) == 0) {
            computeThickness(targets);
            thickness_.bind(VEIL_PHEN_TEX_THICKNESS);
        }
        pass = innerPass(pass);
        const gpu::Framebuffer* fbo = &framebuffer_;
        gpu::PipelineState state = accumulationState(targets);
        // [McGuire16] appendix: all targets add; RT1 rgb: dst * (1 - src) (beta, Eq. 2), a: dst +
        // src.
        state.blend[0] = gpu::BlendState::func(GL_ONE, GL_ONE);
        state.blend[1] = gpu::BlendState::separate(GL_ZERO, GL_ONE_MINUS_SRC_COLOR, GL_ONE, GL_ONE);
        if (params_.refraction) state.blend[2] = gpu::BlendState::func(GL_ONE, GL_ONE);
        // Without diffusion nothing writes D^2 (RT1 alpha stays at its clear value, 0).
        if (!params_.diffusion) state.colorMask[1] = glm::bvec4(true, true, true, false);
        const bool inferAO = params_.inferredAO && targets.ambientOcclusion && pass == 0;
        if (pass == 0) {
            // The surfaces read the opaque depth (z_B of [McGuire16 Eq. 7], the inferred AO, the
            // particles' depth key) while it is attached for the depth test: sample a copy,
            // not a texture in the feedback loop. Nothing reads it without those.
            if (params_.diffusion || inferAO || lowRes())
                glCopyImageSubData(targets.depth->id(), GL_TEXTURE_2D, 0, 0, 0, 0, depthCopy_.id(),
                                   GL_TEXTURE_2D, 0, 0, 0, 0, targets.width, targets.height, 1);
            depthCopy_.bind(VEIL_PHEN_TEX_DEPTH);
        } else {
            // Low-resolution particles: depth key, then a depth test by hand (emit.glsl).
            const gpu::Program& down = programs_.get(downsampleProgram_);
            down.use();
            down.set("phenScale", params_.particleDownsample);
            depthCopy_.bind(VEIL_PHEN_TEX_DEPTH);
            glBindImageTexture(VEIL_IMG_OUTPUT, lowDepth_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                               GL_R32F);
            const glm::ivec4 low = lowRegion(targets);
            dispatchRegion(down, low);
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
            program.use();
            fbo = &lowFramebuffer_;
            state.view(lowWidth_, lowHeight_);
            // A frame's scissor limit (a refinement tile) is in full-resolution pixels: the
            // particles' draws and clears keep to the low-resolution texels the upsampling
            // of the region reads instead (endAccumulate() puts the limit back).
            if (targets.state->scissorLimit()) {
                limitTracker_ = targets.state;
                savedLimit_ = targets.state->scissorLimit();
                targets.state->setScissorLimit(
                    glm::ivec4(low.x, low.y, low.z - low.x, low.w - low.y));
            }
            state.depthTest = false; // emit.glsl tests against the low-resolution depth key
            lowDepth_.bind(VEIL_PHEN_TEX_DEPTH);
        }
        targets.state->apply(state);
        fbo->bind();
        // [McGuire16 Table 2] clear values.
        const float zero[4] = {0, 0, 0, 0}, betaClear[4] = {1, 1, 1, 0};
        glClearNamedFramebufferfv(fbo->id(), GL_COLOR, 0, zero);
        glClearNamedFramebufferfv(fbo->id(), GL_COLOR, 1, betaClear);
        if (params_.refraction) glClearNamedFramebufferfv(fbo->id(), GL_COLOR, 2, zero);
        program.set("phenThicknessRef", params_.thicknessReference)
            .set("phenVolumeBlur", params_.volumeBlur);
        // [McGuire17 sec. 6]: inferred AO needs the frame's AO buffer (render.ao on).
        program.set("phenInferredAO", inferAO ? 1 : 0);
        if (inferAO) targets.ambientOcclusion->bind(VEIL_TEX_AO);
        prepareProgram(pass, program);
    }

    void prepareProgram(int, const gpu::Program& program) const override {
        const float dmax = static_cast<float>(params_.maxDiffusionPixels);
        program.set("phenWeightRange", glm::vec2(params_.weightMin, params_.weightMax))
            .set("phenK0", params_.k0)
            .set("phenK1", params_.k1)
            .set("phenPixelsPerUnit", params_.pixelsPerUnit)
            .set("phenMaxDiffusionPixels", dmax)
            .set("phenRefractionDepth", params_.refractionDepth)
            .set("phenDiffusion", params_.diffusion ? 1 : 0)
            .set("phenRefraction", params_.refraction ? 1 : 0);
    }

    // The fog from compute, in the full-resolution accumulation pass only: the slice-map and
    // particle passes drop media contributions (emit.glsl).
    PerPixelEmit perPixelEmit(int pass) const override {
        return !isThicknessPass(pass) && innerPass(pass) == 0 ? PerPixelEmit::Compute
                                                              : PerPixelEmit::None;
    }
    void bindPerPixelEmit(int, const pass::Context&) const override {
        glBindImageTexture(VEIL_IMG_OIT_TARGET0, accumA_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                           GL_RGBA16F);
        glBindImageTexture(VEIL_IMG_OIT_TARGET0 + 1, betaD_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                           GL_RGBA16);
        if (params_.refraction)
            glBindImageTexture(VEIL_IMG_OIT_TARGET0 + 2, delta_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                               GL_RG16F);
    }

    void endAccumulate(int) override {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (limitTracker_) limitTracker_->setScissorLimit(savedLimit_);
        limitTracker_ = nullptr;
    }

    // The result at a pixel reads A and beta_d at that pixel, and with diffusion the
    // background and the diffusion radius D of the taps within min(D, max_diffusion_pixels) of
    // the pixel moved by its refraction offset [McGuire16 sec. 5]: within refineMarginPx() for
    // offsets up to 16 px; a larger offset reads another tile's accumulation. The background
    // is the opaque image everywhere (targets.opaqueColor during a refinement).
    void resolve(const pass::Context& targets) override {
        if (lowRes()) upsample(targets);
        // The gather reads neighbours of the background while the result is written: read a
        // copy. During a refinement hdrColor holds the opaque image inside the region only:
        // then the copy is of targets.opaqueColor's whole frame (a copy, no shader work).
        const glm::ivec4 r = frameRegion(targets);
        if (targets.opaqueColor)
            glCopyImageSubData(targets.opaqueColor->id(), GL_TEXTURE_2D, 0, 0, 0, 0,
                               background_.id(), GL_TEXTURE_2D, 0, 0, 0, 0, targets.width,
                               targets.height, 1);
        else
            glCopyImageSubData(targets.hdrColor->id(), GL_TEXTURE_2D, 0, r.x, r.y, 0,
                               background_.id(), GL_TEXTURE_2D, 0, r.x, r.y, 0, r.z - r.x,
                               r.w - r.y, 1);
        const gpu::Program& program = programs_.get(resolveProgram_);
        program.use();
        program.set("phenMaxDiffusionPixels", static_cast<float>(params_.maxDiffusionPixels))
            .set("phenSelfModulation", params_.selfModulation ? 1 : 0)
            .set("phenRefraction", params_.refraction ? 1 : 0)
            .set("phenDiffusion", params_.diffusion ? 1 : 0);
        accumA_.bind(VEIL_PHEN_TEX_A);
        betaD_.bind(VEIL_PHEN_TEX_BD);
        if (params_.refraction) delta_.bind(VEIL_PHEN_TEX_DELTA);
        background_.bind(VEIL_PHEN_TEX_BKG);
        glBindImageTexture(VEIL_IMG_OUTPUT, targets.hdrColor->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                           GL_RGBA16F);
        dispatchRegion(program, r);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                        GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
        glBindImageTexture(VEIL_IMG_OUTPUT, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    }

    // The diffusion's taps (up to max_diffusion_pixels), the low-resolution particles'
    // upsampling (two low-resolution texels) and the refraction's offset (bounded here by 16 px:
    // larger offsets read accumulation a tile's margin may miss, so a refined frame can differ
    // there from the frame in one piece).
    int refineMarginPx() const override {
        return (params_.diffusion ? params_.maxDiffusionPixels : 0) +
               (lowRes() ? 2 * params_.particleDownsample : 0) + (params_.refraction ? 16 : 0);
    }
    std::size_t bytesPerPixel() const override {
        const int s = params_.particleDownsample;
        const std::size_t delta = params_.refraction ? 4 : 0;
        return 8 + 8 + delta + 4 + 8 + (lowRes() ? (8 + 8 + delta + 4) / (s * s) : 0) +
               (volume() ? 8 * 16 + 8 : 0);
    }

    // The accumulation targets of [McGuire16 Table 2] (Listing 1): A = weighted premultiplied
    // radiance and coverage, beta_d = transmission (rgb) and diffusion, delta = refraction offsets;
    // thickness with volume_refraction.
    std::vector<Resource> resources() const override {
        std::vector<Resource> r = {{"oit.phenomenological.a", [this] { return &accumA_; }},
                                   {"oit.phenomenological.beta_d", [this] { return &betaD_; }},
                                   {"oit.phenomenological.delta", [this] { return &delta_; }}};
        if (volume())
            r.push_back({"oit.phenomenological.thickness", [this] { return &thickness_; }});
        return r;
    }

private:
    bool lowRes() const { return params_.particleDownsample > 1; }
    // The low-resolution texels the upsampling of the region reads: pixel p's 4 x 4 taps
    // start at floor((p + 0.5) / s - 0.5) - 1 >= floor(p / s) - 2 and end before
    // ceil((p + 1) / s) + 2 (upsample.comp), so the region divided by s, rounded outward and
    // grown by 2 texels.
    glm::ivec4 lowRegion(const pass::Context& targets) const {
        return coarseRegion(frameRegion(targets), params_.particleDownsample, 2,
                            glm::ivec2(lowWidth_, lowHeight_));
    }
    bool volume() const { return params_.volumeRefraction; }
    // RT0 A, RT1 (beta, D^2) and, with refraction, RT2 delta (none without it).
    void attachAccumulation(gpu::Framebuffer& fbo, const gpu::Texture& a, const gpu::Texture& bd,
                            const gpu::Texture& delta) const {
        fbo.attach(GL_COLOR_ATTACHMENT0, a).attach(GL_COLOR_ATTACHMENT1, bd);
        if (params_.refraction) {
            fbo.attach(GL_COLOR_ATTACHMENT2, delta)
                .drawBuffers({GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2});
        } else {
            fbo.drawBuffers({GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1});
        }
    }
    bool isThicknessPass(int pass) const { return volume() && pass == 0; }
    // The pass index without the slice-map pass (0: full resolution, 1: particles).
    int innerPass(int pass) const { return volume() ? pass - 1 : pass; }

    // [Eisemann06 sec. 2]: slice maps of the transparent surfaces, bits OR-ed in 8 RGBA32UI
    // targets, depth-tested against the opaque depth (hidden media do not count).
    void beginSlicePass(const pass::Context& targets) {
        sliceFramebuffer_.bind();
        gpu::PipelineState state = accumulationState(targets);
        targets.state->apply(state);
        const GLuint zero[4] = {0, 0, 0, 0};
        for (int k = 0; k < 8; ++k)
            glClearNamedFramebufferuiv(sliceFramebuffer_.id(), GL_COLOR, k, zero);
        state.logicOp = true;
        state.logicOpMode = GL_OR;
        targets.state->apply(state);
    }

    // [Eisemann06 sec. 3]: the slice maps walked into a thickness per pixel (thickness.comp).
    void computeThickness(const pass::Context& targets) {
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
        const gpu::Program& program = programs_.get(thicknessProgram_);
        program.use();
        for (int k = 0; k < 8; ++k)
            slices_[k].bind(VEIL_PHEN_TEX_SLICES + k);
        glBindImageTexture(VEIL_IMG_OUTPUT, thickness_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                           GL_RG32F);
        dispatchRegion(program, frameRegion(targets)); // per pixel: no neighbourhood
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindImageTexture(VEIL_IMG_OUTPUT, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        // The slice textures sat on the units of the accumulation's inputs: unbind them.
        for (int k = 0; k < 8; ++k)
            glBindTextureUnit(VEIL_PHEN_TEX_SLICES + k, 0);
    }

    // [McGuire16 sec. 5] "Upsample" into the full-resolution buffers (upsample.comp).
    void upsample(const pass::Context& targets) {
        const gpu::Program& program = programs_.get(upsampleProgram_);
        program.use();
        program.set("phenScale", params_.particleDownsample);
        depthCopy_.bind(VEIL_PHEN_TEX_DEPTH);
        lowA_.bind(VEIL_PHEN_TEX_A);
        lowBetaD_.bind(VEIL_PHEN_TEX_BD);
        if (params_.refraction) lowDelta_.bind(VEIL_PHEN_TEX_DELTA);
        lowDepth_.bind(VEIL_PHEN_TEX_BKG);
        glBindImageTexture(0, accumA_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA16F);
        glBindImageTexture(1, betaD_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA16);
        if (params_.refraction)
            glBindImageTexture(2, delta_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RG16F);
        dispatchRegion(program, frameRegion(targets));
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        for (GLuint unit = 0; unit < 3; ++unit)
            glBindImageTexture(unit, 0, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA16F);
    }

    gpu::ProgramManager& programs_;
    PhenomenologicalParams params_;
    std::string name_;
    gpu::ProgramHandle resolveProgram_, downsampleProgram_, upsampleProgram_, thicknessProgram_;
    // The frame's scissor limit while the particle pass replaces it (beginAccumulate()).
    gpu::StateTracker* limitTracker_ = nullptr;
    std::optional<glm::ivec4> savedLimit_;
    std::array<gpu::Texture, 8> slices_{gpu::Texture(gpu::NoCreate), gpu::Texture(gpu::NoCreate),
                                        gpu::Texture(gpu::NoCreate), gpu::Texture(gpu::NoCreate),
                                        gpu::Texture(gpu::NoCreate), gpu::Texture(gpu::NoCreate),
                                        gpu::Texture(gpu::NoCreate), gpu::Texture(gpu::NoCreate)};
    gpu::Texture thickness_{gpu::NoCreate};
    gpu::Framebuffer sliceFramebuffer_{gpu::NoCreate};
    int lowWidth_ = 0, lowHeight_ = 0;
    gpu::Texture lowA_{gpu::NoCreate}, lowBetaD_{gpu::NoCreate}, lowDelta_{gpu::NoCreate};
    gpu::Texture lowDepth_{gpu::NoCreate};
    gpu::Framebuffer lowFramebuffer_{gpu::NoCreate};
    gpu::Texture accumA_{gpu::NoCreate}, betaD_{gpu::NoCreate}, delta_{gpu::NoCreate};
    gpu::Texture depthCopy_{gpu::NoCreate}, background_{gpu::NoCreate};
    gpu::Framebuffer framebuffer_{gpu::NoCreate};
};

} // namespace

static PropertySchema phenomenologicalSchema() {
    const PhenomenologicalParams d;
    PropertySchema s;
    s.real("pixels_per_unit", d.pixelsPerUnit, 0.0, 1e9,
           "W / (2 tan(theta/2)) of the diffusion std-dev; 0 = from the camera",
           "[McGuire16 Eq. 7]")
        .integer("max_diffusion_pixels", d.maxDiffusionPixels, 1, 64,
                 "diffusion kernel radius clamp (D saturates there)", "[McGuire16 Listing 2]")
        .real("k0", d.k0, 0.0, 1e6, "std-dev of one c = 0 surface at unit depth",
              "[McGuire16 Eq. 6-7]")
        .real("k1", d.k1, 1e-9, 1e6, "implied thickness of the scattering surface",
              "[McGuire16 Eq. 7]")
        .real("weight_min", d.weightMin, 1e-9, 1000.0, "lower clamp of the depth weight w",
              "[McGuire16 Eq. 5]")
        .real("weight_max", d.weightMax, 1e-9, 1000.0, "upper clamp of the depth weight w",
              "[McGuire16 Eq. 5]")
        .real("refraction_depth", d.refractionDepth, 1e-9, 1e6,
              "Delta z: background plane distance behind the surface", "[McGuire16 Eq. 9]")
        .boolean("self_modulation", d.selfModulation, "modulate the surface by its own colour",
                 "[McGuire16 Eq. 13], [McGuire17 Eq. 14]")
        .boolean("refraction", d.refraction, "refraction offset in the resolve",
                 "[McGuire16 sec. 5]")
        .boolean("diffusion", d.diffusion, "occlusion-aware diffusion gather in the resolve",
                 "[McGuire16 sec. 5, Listing 2]")
        .integer("particle_downsample", d.particleDownsample, 1, 4,
                 "1, 2 or 4: billboards accumulate at 1/n resolution, bilateral upsampled",
                 "[McGuire16 sec. 5]")
        .boolean("volume_refraction", d.volumeRefraction,
                 "thickness from front/back slice maps scales refraction and absorption",
                 "[Eisemann06 sec. 3]")
        .real("thickness_reference", d.thicknessReference, 0.0, 1e6,
              "medium thickness a transmission t stands for (0 = t not rescaled)",
              "[Eisemann06 sec. 3]")
        .real("volume_blur", d.volumeBlur, 0.0, 1e6, "k_r of the thickness x roughness blur",
              "[Eisemann06 sec. 3]")
        .boolean("inferred_ao", d.inferredAO,
                 "AO inferred at the partial-coverage edges of binary-coverage materials "
                 "(with render.ao on)",
                 "[McGuire17 sec. 6, Listing 2]");
    return s;
}

namespace {

// A factory for each registered name, so name() is the name the technique was asked by (the
// compute rasterizer's refusal, the viewer's technique list and reports name the variant).
template <const char* Name>
std::unique_ptr<Technique> createPhenomenological(gpu::ProgramManager& programs,
                                                  const Properties& properties) {
    return std::make_unique<PhenomenologicalTechnique>(programs, phenomenologicalParams(properties),
                                                       Name);
}
constexpr char kPhenomenological[] = "phenomenological";
constexpr char kNodiff[] = "phenomenological-nodiff";
constexpr char kVolume[] = "phenomenological-volume";

} // namespace

void registerPhenomenological(Registry& registry) {
    registry.add({kPhenomenological,
                  "[McGuire16, McGuire17]: weighted blended OIT with colored transmission, "
                  "diffusion, refraction and self-modulation",
                  nullptr, createPhenomenological<kPhenomenological>, phenomenologicalSchema()});
    // The paper's cost figures are given with and without diffusion; the variant without it
    // (resolve without the gather) is the one the benchmark targets name.
    registry.add({kNodiff,
                  "phenomenological without diffusion (refraction and self-modulation kept)",
                  nullptr, createPhenomenological<kNodiff>,
                  phenomenologicalSchema().withDefault("diffusion", false)});
    // Thickness-dependent refraction and absorption from slice maps [Eisemann06].
    registry.add({kVolume,
                  "phenomenological with volume refraction: per-pixel thickness from front/back "
                  "slice maps scales refraction, Beer-Lambert absorption and roughness blur",
                  nullptr, createPhenomenological<kVolume>,
                  phenomenologicalSchema().withDefault("volume_refraction", true)});
}

} // namespace veil::oit
