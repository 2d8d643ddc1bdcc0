// Moment-based order-independent transparency [Munstermann18].
//
// Parameters (MomentTechniqueParams; defaults from defaultMomentTechniqueParams; properties
// overestimation, bias, wrapping_zone, z_min, z_max declared in registerMoment):
//   overestimation  beta = 0.25           [Munstermann18 sec. 3.2], v_0 of Algorithms 1 and 2
//   bias            float32 per set:      p4 5e-7, p6 5e-6, p8 5e-5, t3 8e-7, t4 1.5e-6
//                   16-bit per set:       p4 6e-5, p6 6e-4, p8 2.5e-3, t3 6.5e-4, t4 8.5e-4
//                   half per set:         the 16-bit ones times kHalfBiasFactor
//                                         (docs/oit.md#moment-constants; [Munstermann18
//                                         secs. 4.1, 5.3])
//   biasVector      power: p4 (0, .375, 0, .375), p6 (0, .48, 0, .451, 0, .45),
//                   p8 (0, .75, 0, .6767, 0, .63, 0, .6003); 16-bit and half: the 16-bit
//                   vectors of docs/oit.md#moment-constants, e.g. p4 (0, .628, 0, .628)
//                   (b' = (1 - bias) b + bias b*); trigonometric: b_j *= (1 - bias), j >= 1
//                   [Munstermann18 sec. 5.3]
//   wrappingZone    theta = pi / 10       [Munstermann18 Eq. 5 and 6] (trigonometric only)
//   zMin, zMax      log-depth warp range  [Munstermann18 sec. 3.3]; default (0) = camera near/far
//
// Passes: geometry pass 0 accumulates b_0 and the moments (emit.glsl: additive blending into
// float32 or half-float targets; storage16.glsl: read-modify-write of 16-bit images under
// GL_ARB_fragment_shader_interlock), geometry pass 1 reconstructs T in front of each fragment
// (Algorithm 1 or 2) and accumulates radiance * T and alpha * T additively, the resolve
// (compute) renormalizes [Munstermann18 Eq. 2].
#include "oit/moment/moment.h"

#include "base/error.h"
#include "shaders/common/bindings.h"

#include <array>

#include <fmt/ranges.h>

namespace veil::oit {

namespace {

// Storage of the moments [Munstermann18 sec. 4.1]:
//   Float32    RGBA32F targets, additive blending only
//   Quantized  b_0 in RGBA16F, normalized moments in 16 bits through the quantization
//              transforms (docs/oit.md#moment-constants), a read-modify-write under
//              GL_ARB_fragment_shader_interlock (storage16.glsl)
//   Half       unnormalized moments in RGBA16F / RG16F and b_0 (with the per-channel b_0) in
//              RGBA32F (b_0 in half doubled t4's error, tests/gl/oit_moment_test.cpp), or
//              in RGBA16F with b0_half (the default of p6-half only: same error there,
//              2.60x instead of 3.23x of blend on oit-bench-1m, bench/RESULTS.md),
//              the accumulation of pass 1 in RGBA16F, additive blending only, so
//              drivers without interlock get half the bandwidth too; rounding errors then
//              accumulate with the fragment count, which the paper counters with a stronger
//              bias, "not ... increased by more than one order of magnitude" [Munstermann18
//              sec. 4.1]
enum class Storage { Float32, Quantized, Half };
// Half storage: the 16-bit column of docs/oit.md#moment-constants (bias and bias vector) times this
// factor ([Munstermann18 sec. 4.1] allows up to 10). Measured in tests/gl/oit_moment_test.cpp
// (HalfStorageErrorWithinFloat32): 5 made every power set worse (p6 2.06x float32's error on
// one scene instead of 1.68x), so the 16-bit values are kept.
constexpr double kHalfBiasFactor = 1.0;

struct Variant {
    const char* name;
    cpu::MomentBasis basis;
    int count;
    Storage storage;
};
constexpr std::array<Variant, 15> kVariants{{
    {"p4", cpu::MomentBasis::Power, 4, Storage::Float32},
    {"p6", cpu::MomentBasis::Power, 6, Storage::Float32},
    {"p8", cpu::MomentBasis::Power, 8, Storage::Float32},
    {"t3", cpu::MomentBasis::Trigonometric, 3, Storage::Float32},
    {"t4", cpu::MomentBasis::Trigonometric, 4, Storage::Float32},
    {"p4-16", cpu::MomentBasis::Power, 4, Storage::Quantized},
    {"p6-16", cpu::MomentBasis::Power, 6, Storage::Quantized},
    {"p8-16", cpu::MomentBasis::Power, 8, Storage::Quantized},
    {"t3-16", cpu::MomentBasis::Trigonometric, 3, Storage::Quantized},
    {"t4-16", cpu::MomentBasis::Trigonometric, 4, Storage::Quantized},
    {"p4-half", cpu::MomentBasis::Power, 4, Storage::Half},
    {"p6-half", cpu::MomentBasis::Power, 6, Storage::Half},
    {"p8-half", cpu::MomentBasis::Power, 8, Storage::Half},
    {"t3-half", cpu::MomentBasis::Trigonometric, 3, Storage::Half},
    {"t4-half", cpu::MomentBasis::Trigonometric, 4, Storage::Half},
}};

const Variant& findVariant(const std::string& name) {
    std::vector<std::string> known;
    for (const Variant& v : kVariants) {
        if (name == v.name) return v;
        known.push_back(v.name);
    }
    throw Error(
        fmt::format("unknown moment OIT variant '{}' (known: {})", name, fmt::join(known, ", ")));
}

class MomentTechnique final : public Technique {
public:
    MomentTechnique(gpu::ProgramManager& programs, const Variant& variant,
                    const MomentTechniqueParams& params)
        : programs_(programs), variant_(variant), params_(params) {
        const bool power = variant.basis == cpu::MomentBasis::Power;
        stored_ = power ? variant.count : 2 * variant.count;
        VEIL_CHECK(!power ||
                       static_cast<int>(params.reconstruction.biasVector.size()) == variant.count,
                   "moment-{}: bias vector needs {} entries", variant.name, variant.count);
        VEIL_CHECK(params.reconstruction.overestimation >= 0.0 &&
                       params.reconstruction.overestimation <= 1.0 &&
                       params.reconstruction.bias >= 0.0 && params.reconstruction.bias < 1.0,
                   "moment-{}: overestimation must lie in [0, 1] and bias in [0, 1)", variant.name);
        VEIL_CHECK(params.zMin <= 0.0 || params.zMax > params.zMin,
                   "moment-{}: depth range [{}, {}] must satisfy 0 < min < max", variant.name,
                   params.zMin, params.zMax);
        resolveProgram_ = programs_.add(gpu::ProgramDesc::compute("oit/moment/resolve.comp"));
    }

    std::string name() const override { return std::string("moment-") + variant_.name; }
    std::filesystem::path emitInclude() const override { return "oit/moment/emit.glsl"; }
    int geometryPasses() const override { return 2; }

    std::vector<std::string> defines(int pass) const override {
        std::vector<std::string> d{variant_.basis == cpu::MomentBasis::Power ? "MOMENT_POWER 1"
                                                                             : "MOMENT_TRIG 1",
                                   fmt::format("MOMENT_COUNT {}", variant_.count),
                                   fmt::format("MOMENT_STORED {}", stored_), biasVectorDefine()};
        // Image formats of the additive targets, for per-pixel emission from compute.
        for (int i = 0; i < momentTargets(); ++i)
            d.push_back(fmt::format("MOMENT_FORMAT{} {}", i, imageFormatName(momentFormat(i))));
        d.push_back(fmt::format("MOMENT_ACCUM_FORMAT {}", imageFormatName(accumFormat())));
        if (quantized()) {
            d.push_back("MOMENT_STORAGE16 1");
            // The loader writes defines right after #version, the one place an #extension
            // may go. Pass 1 only reads the moments and needs no interlock; the per-pixel
            // emission from compute (OIT_COMPUTE, defined before these) needs none either.
            if (pass == 0)
                d.push_back("MOMENT_INTERLOCK 1\n#ifndef OIT_COMPUTE\n#extension "
                            "GL_ARB_fragment_shader_interlock : require\n#endif");
        }
        return d;
    }

    PerPixelEmit perPixelEmit(int) const override { return PerPixelEmit::Compute; }

    void bindPerPixelEmit(int pass, const pass::Context&) const override {
        // The 16-bit storage's images are bound by beginAccumulate (pass 0).
        if (pass == 0 && quantized()) return;
        if (pass == 0) {
            for (int i = 0; i < momentTargets(); ++i)
                glBindImageTexture(VEIL_IMG_OIT_TARGET0 + i, moments_[i].id(), 0, GL_FALSE, 0,
                                   GL_READ_WRITE, momentFormat(i));
        } else {
            glBindImageTexture(VEIL_IMG_OIT_TARGET0, accum_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                               accumFormat());
        }
    }

    void resize(const pass::Context& targets) override {
        auto make = [&](GLenum format) {
            gpu::Texture t(GL_TEXTURE_2D);
            t.storage2D(1, format, targets.width, targets.height)
                .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
                .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            return t;
        };
        moments_.clear();
        for (int i = 0; i < momentTargets(); ++i)
            moments_.push_back(make(momentFormat(i)));
        accum_ = make(accumFormat());
        momentFbo_ = gpu::Framebuffer();
        momentFbo_.attach(GL_DEPTH_ATTACHMENT, *targets.depth);
        if (quantized()) {
            momentFbo_.drawBuffers({GL_NONE}); // moments go through images; depth test only
        } else {
            for (int i = 0; i < momentTargets(); ++i)
                momentFbo_.attach(GL_COLOR_ATTACHMENT0 + i, moments_[i]);
            if (momentTargets() == 2)
                momentFbo_.drawBuffers({GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1});
            else
                momentFbo_.drawBuffers(
                    {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2});
        }
        momentFbo_.checkComplete("oit/moment (moments)");
        accumFbo_ = gpu::Framebuffer();
        accumFbo_.attach(GL_COLOR_ATTACHMENT0, accum_)
            .attach(GL_DEPTH_ATTACHMENT, *targets.depth)
            .drawBuffers({GL_COLOR_ATTACHMENT0});
        accumFbo_.checkComplete("oit/moment (accumulation)");
    }

    void beginAccumulate(int pass, const pass::Context& targets,
                         const gpu::Program& program) override {
        gpu::PipelineState state = accumulationState(targets);
        if (pass != 0 || !quantized())
            state.blendAll(
                gpu::BlendState::func(GL_ONE, GL_ONE)); // [Munstermann18]: additive passes
        targets.state->apply(state);
        const float zero[4] = {0, 0, 0, 0};
        if (pass == 0) {
            momentFbo_.bind();
            for (int i = 0; i < momentTargets(); ++i) {
                if (quantized()) {
                    glClearTexImage(moments_[i].id(), 0, GL_RGBA, GL_FLOAT, zero);
                    glBindImageTexture(VEIL_IMG_MOMENT0 + i, moments_[i].id(), 0, GL_FALSE, 0,
                                       GL_READ_WRITE, momentFormat(i));
                } else {
                    glClearNamedFramebufferfv(momentFbo_.id(), GL_COLOR, i, zero);
                }
            }
        } else {
            accumFbo_.bind();
            glClearNamedFramebufferfv(accumFbo_.id(), GL_COLOR, 0, zero);
            for (int i = 0; i < momentTargets(); ++i)
                moments_[i].bind(VEIL_TEX_OIT0 + i);
        }
        prepareProgram(pass, program);
    }

    void prepareProgram(int, const gpu::Program& program) const override {
        const cpu::MomentParams& r = params_.reconstruction;
        program.set("momentOverestimation", static_cast<float>(r.overestimation))
            .set("momentBias", static_cast<float>(r.bias))
            .set("momentWrappingZone", static_cast<float>(r.wrappingZone))
            .set("momentDepthRange", glm::vec2(params_.zMin, params_.zMax));
    }

    void endAccumulate(int pass) override {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (pass == 0 && quantized()) {
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            for (int i = 0; i < momentTargets(); ++i)
                glBindImageTexture(VEIL_IMG_MOMENT0 + i, 0, 0, GL_FALSE, 0, GL_READ_WRITE,
                                   GL_RGBA16F);
        }
    }

    void resolve(const pass::Context& targets) override {
        const gpu::Program& program = programs_.get(resolveProgram_);
        program.use();
        moments_[0].bind(VEIL_TEX_OIT0 + 0);
        accum_.bind(VEIL_TEX_OIT0 + 3);
        glBindImageTexture(VEIL_IMG_OUTPUT, targets.hdrColor->id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                           GL_RGBA16F);
        dispatchRegion(program, frameRegion(targets));
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                        GL_FRAMEBUFFER_BARRIER_BIT);
    }

    std::size_t bytesPerPixel() const override {
        std::size_t bytes = formatBytes(accumFormat());
        for (int i = 0; i < momentTargets(); ++i)
            bytes += formatBytes(momentFormat(i));
        return bytes;
    }

    // Geometry pass 0 ([Munstermann18 Algorithm 1/2] inputs): moments0 holds b_0, moments1..2 the
    // power or trigonometric moments (momentFormat); pass 1: accum = sum of radiance * T (rgb) and
    // alpha * T (a), renormalized by the resolve [Munstermann18 Eq. 2].
    std::vector<Resource> resources() const override {
        std::vector<Resource> r;
        for (int i = 0; i < momentTargets(); ++i)
            r.push_back({fmt::format("oit.{}.moments{}", name(), i), [this, i] {
                             const auto k = static_cast<std::size_t>(i);
                             return k < moments_.size() ? &moments_[k] : nullptr;
                         }});
        r.push_back({fmt::format("oit.{}.accum", name()), [this] { return &accum_; }});
        return r;
    }

private:
    // The bias vector as a constant array: it is fixed per technique instance.
    std::string biasVectorDefine() const {
        std::array<double, 8> v{};
        const auto& bv = params_.reconstruction.biasVector;
        for (std::size_t i = 0; i < bv.size() && i < v.size(); ++i)
            v[i] = bv[i];
        return fmt::format("MOMENT_BIAS_VECTOR float[8]({:.17g})", fmt::join(v, ", "));
    }
    bool quantized() const { return variant_.storage == Storage::Quantized; }
    int momentTargets() const { return stored_ > 4 ? 3 : 2; }
    // Target 0 holds (b_0, b_0 rgb); targets 1, 2 the moments (emit.glsl, storage16.glsl).
    // Target 2 holds moments 5..MOMENT_STORED: two channels where 6 are stored.
    GLenum momentFormat(int target) const {
        const bool two = target == 2 && stored_ == 6;
        switch (variant_.storage) {
        case Storage::Float32:
            return GL_RGBA32F;
        case Storage::Half:
            if (target == 0) return params_.b0Half ? GL_RGBA16F : GL_RGBA32F;
            return two ? GL_RG16F : GL_RGBA16F;
        case Storage::Quantized:
            if (target == 0) return GL_RGBA16F;
            if (variant_.basis == cpu::MomentBasis::Trigonometric) return GL_RGBA16_SNORM;
            return two ? GL_RG16 : GL_RGBA16;
        }
        return GL_RGBA32F;
    }
    static const char* imageFormatName(GLenum format) {
        switch (format) {
        case GL_RGBA32F:
            return "rgba32f";
        case GL_RGBA16F:
            return "rgba16f";
        case GL_RG16F:
            return "rg16f";
        case GL_RGBA16:
            return "rgba16";
        case GL_RG16:
            return "rg16";
        default:
            return "rgba16_snorm";
        }
    }
    static std::size_t formatBytes(GLenum format) {
        switch (format) {
        case GL_RGBA32F:
            return 16;
        case GL_RG16F:
        case GL_RG16:
            return 4;
        default:
            return 8; // RGBA16F, RGBA16, RGBA16_SNORM
        }
    }
    GLenum accumFormat() const {
        return variant_.storage == Storage::Half ? GL_RGBA16F : GL_RGBA32F;
    }

    gpu::ProgramManager& programs_;
    Variant variant_;
    MomentTechniqueParams params_;
    int stored_ = 0;
    gpu::ProgramHandle resolveProgram_;
    std::vector<gpu::Texture> moments_;
    gpu::Texture accum_{gpu::NoCreate};
    gpu::Framebuffer momentFbo_{gpu::NoCreate}, accumFbo_{gpu::NoCreate};
};

} // namespace

MomentTechniqueParams defaultMomentTechniqueParams(const std::string& variant) {
    const Variant& v = findVariant(variant);
    MomentTechniqueParams p;
    p.reconstruction = cpu::defaultMomentParams({v.basis, v.count}, v.storage != Storage::Float32);
    if (v.storage == Storage::Half) p.reconstruction.bias *= kHalfBiasFactor;
    // p6 only: b_0 in RGBA16F measured the same error as in RGBA32F on the GL test scenes
    // (HalfB0StorageErrorWithinFloat32: 1.16x / 1.17x / 1.69x float32's vs 1.18x / 1.16x /
    // 1.68x) for 8 bytes per pixel less; t4 doubled its error with it, so the others keep
    // float32.
    p.b0Half = variant == "p6-half";
    return p;
}

std::unique_ptr<Technique> createMomentTechnique(gpu::ProgramManager& programs,
                                                 const std::string& variant,
                                                 const MomentTechniqueParams& params) {
    return std::make_unique<MomentTechnique>(programs, findVariant(variant), params);
}

void registerMoment(Registry& registry) {
    for (const Variant& v : kVariants) {
        const std::string variant = v.name;
        const bool trig = v.basis == cpu::MomentBasis::Trigonometric;
        const MomentTechniqueParams defaults = defaultMomentTechniqueParams(variant);
        PropertySchema schema;
        schema
            .real("overestimation", defaults.reconstruction.overestimation, 0.0, 1.0,
                  "beta: weight of the upper bound in the reconstructed absorbance",
                  "[Munstermann18 sec. 3.2], v_0 of Alg. 1/2")
            .real("bias", defaults.reconstruction.bias, 0.0, 0.999,
                  "moment biasing alpha against rounding (per set and storage)",
                  "[Munstermann18 sec. 4.1, 5.3]; docs/oit.md#moment-constants");
        if (trig)
            schema.real("wrapping_zone", defaults.reconstruction.wrappingZone, 1e-3, 3.14159,
                        "theta of the wrapping zone of the trigonometric bound",
                        "[Munstermann18 Eq. 5, 6]");
        schema
            .real("z_min", 0.0, 0.0, 1e30,
                  "near end of the log-depth warp (0 = the camera's near plane)",
                  "[Munstermann18 sec. 3.3]")
            .real("z_max", 0.0, 0.0, 1e30,
                  "far end of the log-depth warp (0 = the camera's far plane)",
                  "[Munstermann18 sec. 3.3]");
        const bool half = v.storage == Storage::Half;
        if (half)
            schema.boolean("b0_half", defaults.b0Half,
                           "b_0 and its per-channel values in RGBA16F instead of RGBA32F",
                           "[Munstermann18 sec. 4.1]");
        std::function<bool(const gpu::ContextInfo&)> available;
        if (v.storage == Storage::Quantized)
            available = [](const gpu::ContextInfo& c) { return c.fragmentShaderInterlock; };
        registry.add(
            {std::string("moment-") + v.name,
             fmt::format("moment-based OIT [Munstermann18], {} {} moments, {} storage", v.count,
                         v.basis == cpu::MomentBasis::Power ? "power" : "trigonometric",
                         v.storage == Storage::Quantized
                             ? "16-bit (needs fragment shader interlock)"
                         : v.storage == Storage::Half ? "half-float, additive"
                                                      : "float32"),
             available,
             [variant, trig, half](gpu::ProgramManager& programs, const Properties& p) {
                 MomentTechniqueParams params = defaultMomentTechniqueParams(variant);
                 params.reconstruction.overestimation = p.getDouble("overestimation");
                 params.reconstruction.bias = p.getDouble("bias");
                 if (trig) params.reconstruction.wrappingZone = p.getDouble("wrapping_zone");
                 params.zMin = p.getDouble("z_min");
                 params.zMax = p.getDouble("z_max");
                 if (half) params.b0Half = p.getBool("b0_half");
                 return createMomentTechnique(programs, variant, params);
             },
             std::move(schema)});
    }
}

} // namespace veil::oit
