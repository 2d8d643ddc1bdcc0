// Stochastic transparency [Enderton11]. Parameter block:
//
//   name               default  paper                      meaning
//   samples (S)        8        [Enderton11 sec. 3.1, 3.5, sec. 5]    MSAA samples per pixel per
//   pass,
//                                                          min(requested, GL_MAX_SAMPLES,
//                                                          colour/depth texture limits, 32);
//                                                          llvmpipe gives 4
//   passes             1        [Enderton11 sec. 3.5, sec. 5],        repeats with different seeds;
//                               footnotes 3 and 4          total samples = S x passes. When
//                                                          S x passes <= 32, one stratified
//                                                          mask of S x passes bits is split
//                                                          across the passes (footnote 3);
//                                                          otherwise each pass draws its own
//                                                          S-bit mask
//   seed               pass::Context::seed    [Enderton11 sec. 6]   hashed with pixel, primitive id
//                                                          and depth into the mask choice;
//                                                          same seed, same image
//   mask table         all C(N,R) masks for N <= 16, else 16384 distinct random ones per R
//                      ([Enderton11 sec. 5] lookup table; src/oit/cpu/stochastic.cpp)
//
// Geometry passes (geometryPasses(), P = passes):
//   stochastic        P x [stochastic colour]                        [Enderton11 sec. 3.1]
//   stochastic-alpha  [total alpha] + P x [stochastic colour]        ([Enderton11 sec. 3.3, 3.5]
//   basic) stochastic-depth  [total alpha] + P x [stochastic depth, accumulation]   [Enderton11
//   sec. 3.4, 3.5]
// i.e. 1 + 2P passes for the depth-based method, as [Enderton11 sec. 3.5] counts them.
//
// Opaque depth: the frame's depth is single-sample; before every pass that z-tests, a
// fullscreen fragment pass (copy_depth.frag, depth func ALWAYS) writes it into all samples of
// the technique's own multisampled DEPTH_COMPONENT32F texture, which the stochastic passes
// then test (and the stochastic passes write) per sample. Skipped where no pass wrote depth
// since the last copy (the first stochastic pass after the total-alpha pass): P copies per
// frame for stochastic-alpha and -depth instead of 1 + P (stats() "depth_copies").
#include "oit/stochastic/stochastic.h"

#include "base/error.h"
#include "oit/cpu/stochastic.h"
#include "shaders/common/bindings.h"

#include <algorithm>
#include <fmt/format.h>

namespace veil::oit {

namespace {

enum class PassKind { TotalAlpha = 0, StochColor = 1, StochDepth = 2, Accumulate = 3 };

struct PassInfo {
    PassKind kind;
    int repeat;
};

class StochasticTechnique final : public Technique {
public:
    StochasticTechnique(StochasticMode mode, const StochasticParams& params,
                        gpu::ProgramManager& programs)
        : mode_(mode), programs_(&programs) {
        samples_ = stochasticEffectiveSamples(params.samples);
        passes_ = params.passes;
        const int total = samples_ * passes_;
        grouped_ = total <= cpu::kStochasticMaxMaskBits;
        maskBits_ = grouped_ ? total : samples_;
        const cpu::StochasticMaskTable table = cpu::buildStochasticMaskTable(maskBits_);
        std::vector<std::uint32_t> data;
        data.reserve(2 * (cpu::kStochasticMaxMaskBits + 1) + table.masks.size());
        data.insert(data.end(), table.offset.begin(), table.offset.end());
        data.insert(data.end(), table.count.begin(), table.count.end());
        data.insert(data.end(), table.masks.begin(), table.masks.end());
        masks_ = gpu::Buffer();
        masks_.setStorage(std::span<const std::uint32_t>(data), 0);

        using gpu::ProgramDesc;
        copyProgram_ = programs.add(ProgramDesc::graphics("oit/stochastic/copy_depth.vert",
                                                          "oit/stochastic/copy_depth.frag"));
        foldProgram_ = programs.add(ProgramDesc::compute("oit/stochastic/fold.comp"));
        resolveProgram_ = programs.add(ProgramDesc::compute("oit/stochastic/resolve.comp"));
        vao_ = gpu::VertexArray();
    }

    std::string name() const override {
        switch (mode_) {
        case StochasticMode::Basic:
            return "stochastic";
        case StochasticMode::AlphaCorrected:
            return "stochastic-alpha";
        case StochasticMode::DepthBased:
            return "stochastic-depth";
        }
        return "stochastic";
    }
    std::filesystem::path emitInclude() const override { return "oit/stochastic/emit.glsl"; }

    std::vector<std::string> defines(int pass) const override {
        return {fmt::format("STOCH_KIND {}", static_cast<int>(passInfo(pass).kind))};
    }

    int geometryPasses() const override {
        switch (mode_) {
        case StochasticMode::Basic:
            return passes_;
        case StochasticMode::AlphaCorrected:
            return 1 + passes_;
        case StochasticMode::DepthBased:
            return 1 + 2 * passes_;
        }
        return passes_;
    }

    void resize(const pass::Context& targets) override {
        VEIL_CHECK(targets.hdrColor && targets.depth && targets.width > 0 && targets.height > 0,
                   "{}: frame targets missing", name());
        VEIL_CHECK(targets.hdrColor->format() == GL_RGBA16F,
                   "{}: the resolve writes an RGBA16F HDR target (got format 0x{:x})", name(),
                   targets.hdrColor->format());
        const int w = targets.width, h = targets.height;
        msDepth_ = gpu::Texture(GL_TEXTURE_2D_MULTISAMPLE);
        msDepth_.storage2DMultisample(samples_, GL_DEPTH_COMPONENT32F, w, h);
        msColor_ = gpu::Texture(GL_TEXTURE_2D_MULTISAMPLE);
        msColor_.storage2DMultisample(samples_, GL_RGBA16F, w, h);
        depthFbo_ = gpu::Framebuffer();
        depthFbo_.attach(GL_DEPTH_ATTACHMENT, msDepth_).drawBuffers({GL_NONE});
        depthFbo_.checkComplete("oit/stochastic depth");
        colorFbo_ = gpu::Framebuffer();
        colorFbo_.attach(GL_COLOR_ATTACHMENT0, msColor_)
            .attach(GL_DEPTH_ATTACHMENT, msDepth_)
            .drawBuffers({GL_COLOR_ATTACHMENT0});
        colorFbo_.checkComplete("oit/stochastic colour");
        if (mode_ != StochasticMode::Basic) {
            msTotal_ = gpu::Texture(GL_TEXTURE_2D_MULTISAMPLE);
            msTotal_.storage2DMultisample(samples_, GL_RGBA16F, w, h);
            totalFbo_ = gpu::Framebuffer();
            totalFbo_.attach(GL_COLOR_ATTACHMENT0, msTotal_)
                .attach(GL_DEPTH_ATTACHMENT, msDepth_)
                .drawBuffers({GL_COLOR_ATTACHMENT0});
            totalFbo_.checkComplete("oit/stochastic total alpha");
        }
        if (mode_ != StochasticMode::DepthBased) {
            passSum_ = gpu::Texture(GL_TEXTURE_2D);
            passSum_.storage2D(1, GL_RGBA32F, w, h);
        }
        // Texture units the resolve samples even when a variant does not use them.
        dummyMs_ = gpu::Texture(GL_TEXTURE_2D_MULTISAMPLE);
        dummyMs_.storage2DMultisample(samples_, GL_RGBA16F, 1, 1);
        dummy2d_ = gpu::Texture(GL_TEXTURE_2D);
        dummy2d_.storage2D(1, GL_RGBA32F, 1, 1);
    }

    void prepareProgram(int pass, const gpu::Program& program) const override {
        const PassInfo info = passInfo(pass);
        if (info.kind != PassKind::StochColor && info.kind != PassKind::StochDepth) return;
        const bool grouped = grouped_;
        program.set("stochSeed", static_cast<unsigned>(seed_))
            .set("stochGroup", static_cast<unsigned>(grouped ? 0 : info.repeat))
            .set("stochShift", grouped ? info.repeat * samples_ : 0)
            .set("stochBits", maskBits_)
            .set("stochSamples", samples_);
    }

    void beginAccumulate(int pass, const pass::Context& targets,
                         const gpu::Program& program) override {
        const PassInfo info = passInfo(pass);
        region_ = frameRegion(targets);
        gpu::PipelineState state = accumulationState(targets); // multisampling on (default)
        targets.state->apply(state); // clears obey the colour masks: state first
        if (pass == 0) clearAccumulation();
        // Every pass that writes depth starts from the opaque depth; the total-alpha pass
        // (pass 0) also needs it. Only passes that write depth (stochastic colour or depth)
        // change it: the first of those after the total-alpha pass finds the copy intact.
        if (pass == 0) {
            msDepthHoldsOpaque_ = false;
            depthCopies_ = 0;
        }
        if (info.kind != PassKind::Accumulate && !msDepthHoldsOpaque_) copyOpaqueDepth(targets);
        msDepthHoldsOpaque_ = info.kind == PassKind::TotalAlpha ||
                              (msDepthHoldsOpaque_ && info.kind == PassKind::Accumulate);
        switch (info.kind) {
        case PassKind::TotalAlpha: // [Enderton11 sec. 3.5 step 2], multiplicative blend
            totalFbo_.bind();
            state.blendAll(gpu::BlendState::func(GL_ZERO, GL_SRC_COLOR));
            targets.state->apply(state);
            break;
        case PassKind::StochColor:   // [Enderton11 sec. 3.1]: winner take all per sample
        case PassKind::StochDepth: { // [Enderton11 sec. 3.5] depth-based step 3: z only
            state.depth(GL_LESS, true);
            targets.state->apply(state);
            if (info.kind == PassKind::StochColor) {
                const float zero[4] = {0, 0, 0, 0};
                glClearNamedFramebufferfv(colorFbo_.id(), GL_COLOR, 0, zero);
                colorFbo_.bind();
            } else {
                depthFbo_.bind();
            }
            masks_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_STOCH_MASKS);
            seed_ = targets.seed;
            prepareProgram(pass, program);
            break;
        }
        case PassKind::Accumulate: // [Enderton11 sec. 3.5 step 4]: add to samples where z_frag <=
                                   // z_buffer
            colorFbo_.bind();
            state.depth(GL_LEQUAL, false);
            // The fragment must pass against the depth it stored in the stochastic pass, drawn
            // by another program: a minimal offset toward the eye absorbs rasterization
            // differences between the two programs (GL guarantees invariance only with
            // `invariant gl_Position`, which mesh.vert does not declare).
            state.polygonOffsetFill = true;
            state.polygonOffsetFactor = 0.0f;
            state.polygonOffsetUnits = -1.0f;
            state.blendAll(gpu::BlendState::func(GL_ONE, GL_ONE));
            targets.state->apply(state);
            break;
        }
    }

    void endAccumulate(int pass) override {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (passInfo(pass).kind == PassKind::StochColor) {
            const gpu::Program& fold = programs_->get(foldProgram_);
            fold.use();
            fold.set("samples", samples_);
            msColor_.bind(VEIL_TEX_OIT0 + 1);
            glBindImageTexture(VEIL_IMG_OUTPUT, passSum_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                               GL_RGBA32F);
            dispatchRegion(fold, region_); // the region of beginAccumulate()
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
        }
    }

    void resolve(const pass::Context& targets) override {
        const gpu::Program& program = programs_->get(resolveProgram_);
        program.use();
        program.set("variant", static_cast<int>(mode_))
            .set("samples", samples_)
            .set("passes", passes_);
        (mode_ != StochasticMode::Basic ? msTotal_ : dummyMs_).bind(VEIL_TEX_OIT0 + 0);
        (mode_ == StochasticMode::DepthBased ? msColor_ : dummyMs_).bind(VEIL_TEX_OIT0 + 1);
        (mode_ != StochasticMode::DepthBased ? passSum_ : dummy2d_).bind(VEIL_TEX_OIT0 + 2);
        glBindImageTexture(VEIL_IMG_OUTPUT, targets.hdrColor->id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                           GL_RGBA16F);
        dispatchRegion(program, frameRegion(targets));
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                        GL_FRAMEBUFFER_BARRIER_BIT);
    }

    nlohmann::json stats() const override {
        // S after the driver's clamp: what the image was made with.
        return {{"effective_samples", samples_},
                {"passes", passes_},
                {"mask_bits", maskBits_},
                {"geometry_passes", geometryPasses()},
                {"depth_copies", depthCopies_}};
    }

    std::size_t bytesPerPixel() const override {
        std::size_t perSample = 4 + 8; // depth + colour
        if (mode_ != StochasticMode::Basic) perSample += 8;
        std::size_t bytes = perSample * static_cast<std::size_t>(samples_);
        if (mode_ != StochasticMode::DepthBased) bytes += 16;
        return bytes;
    }

    // The per-sample colour (and total alpha) are multisample (listed, not readable); the
    // sum over passes is a plain RGBA32F target.
    std::vector<Resource> resources() const override {
        std::vector<Resource> r = {
            {fmt::format("oit.{}.color", name()), [this] { return &msColor_; }}};
        if (mode_ != StochasticMode::Basic)
            r.push_back({fmt::format("oit.{}.total_alpha", name()), [this] { return &msTotal_; }});
        if (mode_ != StochasticMode::DepthBased)
            r.push_back({fmt::format("oit.{}.pass_sum", name()), [this] { return &passSum_; }});
        return r;
    }

private:
    PassInfo passInfo(int pass) const {
        VEIL_CHECK(pass >= 0 && pass < geometryPasses(), "{}: geometry pass {} out of 0..{}",
                   name(), pass, geometryPasses() - 1);
        switch (mode_) {
        case StochasticMode::Basic:
            return {PassKind::StochColor, pass};
        case StochasticMode::AlphaCorrected:
            return pass == 0 ? PassInfo{PassKind::TotalAlpha, 0}
                             : PassInfo{PassKind::StochColor, pass - 1};
        case StochasticMode::DepthBased:
            if (pass == 0) return {PassKind::TotalAlpha, 0};
            return {(pass - 1) % 2 == 0 ? PassKind::StochDepth : PassKind::Accumulate,
                    (pass - 1) / 2};
        }
        return {PassKind::StochColor, pass};
    }

    void clearAccumulation() {
        const float zero[4] = {0, 0, 0, 0}, one[4] = {1, 1, 1, 1};
        if (mode_ != StochasticMode::Basic)
            glClearNamedFramebufferfv(totalFbo_.id(), GL_COLOR, 0, one);
        if (mode_ == StochasticMode::DepthBased)
            glClearNamedFramebufferfv(colorFbo_.id(), GL_COLOR, 0, zero);
        else // not a framebuffer clear: kept to the region by hand
            glClearTexSubImage(passSum_.id(), 0, region_.x, region_.y, 0, region_.z - region_.x,
                               region_.w - region_.y, 1, GL_RGBA, GL_FLOAT, zero);
    }

    void copyOpaqueDepth(const pass::Context& targets) {
        ++depthCopies_;
        depthFbo_.bind();
        gpu::PipelineState state;
        state.view(targets.width, targets.height).depth(GL_ALWAYS, true);
        targets.state->apply(state);
        const gpu::Program& copy = programs_->get(copyProgram_);
        copy.use();
        targets.depth->bind(VEIL_TEX_OIT0 + 3);
        vao_.bind();
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glBindVertexArray(0);
    }

    StochasticMode mode_;
    gpu::ProgramManager* programs_;
    int samples_ = 4, passes_ = 1, maskBits_ = 4;
    bool grouped_ = true;
    bool msDepthHoldsOpaque_ = false; // msDepth_ = the opaque depth (no pass wrote it since)
    int depthCopies_ = 0;             // full-screen MSAA depth copies of the last frame (stats())
    std::uint32_t seed_ = 1;          // pass::Context::seed of the current frame
    glm::ivec4 region_{0};            // frameRegion() of the current geometry pass
    gpu::ProgramHandle copyProgram_, foldProgram_, resolveProgram_;
    gpu::Buffer masks_{gpu::NoCreate};
    gpu::VertexArray vao_{gpu::NoCreate};
    gpu::Texture msDepth_{gpu::NoCreate}, msColor_{gpu::NoCreate}, msTotal_{gpu::NoCreate};
    gpu::Texture passSum_{gpu::NoCreate}, dummyMs_{gpu::NoCreate}, dummy2d_{gpu::NoCreate};
    gpu::Framebuffer depthFbo_{gpu::NoCreate}, colorFbo_{gpu::NoCreate}, totalFbo_{gpu::NoCreate};
};

void add(Registry& registry, const char* id, StochasticMode mode, const char* description) {
    PropertySchema schema;
    schema
        .integer("samples", 8, 1, 64,
                 "MSAA samples per pixel per pass, S (clamped to the driver's limits and 32)",
                 "[Enderton11 sec. 3.1, 3.5]")
        .integer("passes", 1, 1, 64,
                 "passes with different seeds; total samples per pixel = S x passes",
                 "[Enderton11 sec. 3.5, sec. 5]");
    registry.add({id, description, [](const gpu::ContextInfo& c) { return c.maxSamples >= 2; },
                  [mode](gpu::ProgramManager& programs, const Properties& p) {
                      const StochasticParams params{p.getInt("samples"), p.getInt("passes")};
                      return std::make_unique<StochasticTechnique>(mode, params, programs);
                  },
                  std::move(schema)});
}

} // namespace

int stochasticEffectiveSamples(int requested) {
    GLint maxSamples = 0, maxColor = 0, maxDepth = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    glGetIntegerv(GL_MAX_COLOR_TEXTURE_SAMPLES, &maxColor);
    glGetIntegerv(GL_MAX_DEPTH_TEXTURE_SAMPLES, &maxDepth);
    const int limit = std::min({maxSamples, maxColor, maxDepth, cpu::kStochasticMaxMaskBits});
    VEIL_CHECK(limit >= 1, "stochastic transparency: the GL driver reports no MSAA support");
    return std::clamp(requested, 1, limit);
}

void registerStochastic(Registry& registry) {
    add(registry, "stochastic", StochasticMode::Basic,
        "stochastic transparency, basic stratified S-choose-R masks [Enderton11 sec. 3.1]");
    add(registry, "stochastic-alpha", StochasticMode::AlphaCorrected,
        "stochastic transparency with alpha correction [Enderton11 sec. 3.3]");
    add(registry, "stochastic-depth", StochasticMode::DepthBased,
        "depth-based stochastic transparency [Enderton11 sec. 3.4/3.5]");
}

} // namespace veil::oit
