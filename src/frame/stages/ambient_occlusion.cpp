#include "frame/stages/ambient_occlusion.h"

#include "base/error.h"
#include "shaders/common/bindings.h"

#include <algorithm>

namespace veil::frame {

namespace {
void dispatch(int width, int height) {
    glDispatchCompute((width + 7) / 8, (height + 7) / 8, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}
} // namespace

const PropertySchema& AmbientOcclusion::schema() {
    static const PropertySchema s = [] {
        const char* sao = "SAO [McGuire12], as in [Mara16]";
        PropertySchema p;
        p.boolean("enabled", false, "screen-space ambient obscurance on opaque surfaces", sao)
            .real("radius", 0.5, 1e-6, 1e6, "world radius r of the sampled neighbourhood", sao)
            .real("intensity", 1.0, 0.0, 1e3, "sigma: scale of the obscurance sum", sao)
            .real("contrast", 1.0, 0.01, 16.0, "k: exponent of 1 - obscurance (sharpness)", sao)
            .real("bias", 0.01, 0.0, 1.0, "beta: depth-scaled bias against facet self-shadowing",
                  sao)
            .real("epsilon", 0.01, 1e-9, 1e3, "epsilon of the 1 / (|v|^2 + epsilon) falloff", sao)
            .integer("samples", 11, 1, 64, "s: samples per pixel on the spiral", sao)
            .integer("spiral_turns", 7, 1, 64, "tau: turns of the sample spiral", sao)
            .integer("mip_levels", 5, 1, 8, "levels of the camera-space z pyramid", sao)
            .integer("blur_radius", 4, 0, 8, "R: bilateral blur taps each side (0 = off)", sao)
            .integer("blur_stride", 2, 1, 4, "pixels between blur taps", sao)
            .real("blur_sharpness", 20.0, 0.0, 1e6,
                  "depth weight max(0, 1 - sharpness |dz| / z) of the blur", sao);
        return p;
    }();
    return s;
}

AmbientOcclusion::AmbientOcclusion(gpu::ProgramManager& programs, Properties properties)
    : programs_(programs), properties_(std::move(properties)) {
    using gpu::ProgramDesc;
    cszProgram_ = programs_.add(ProgramDesc::compute("frame/ao/csz.comp"));
    downsampleProgram_ = programs_.add(ProgramDesc::compute("frame/ao/csz_downsample.comp"));
    saoProgram_ = programs_.add(ProgramDesc::compute("frame/ao/sao.comp"));
    blurProgram_ = programs_.add(ProgramDesc::compute("frame/ao/blur.comp"));
}

void AmbientOcclusion::resize(int width, int height) {
    width_ = width;
    height_ = height;
    int possible = 1;
    while ((std::max(width, height) >> possible) > 0)
        ++possible;
    levels_ = std::min(properties_.getInt("mip_levels"), possible);
    auto make = [](GLenum format, int levels, int w, int h) {
        gpu::Texture t(GL_TEXTURE_2D);
        t.storage2D(levels, format, w, h)
            .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST)
            .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
            .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        return t;
    };
    csz_ = make(GL_R32F, levels_, width, height);
    raw_ = make(GL_R16F, 1, width, height);
    if (properties_.getInt("blur_radius") > 0) {
        tmp_ = make(GL_R16F, 1, width, height);
        blurred_ = make(GL_R16F, 1, width, height);
    }
}

void AmbientOcclusion::estimate(const gpu::Texture& depth) const {
    const gpu::Program& csz = programs_.get(cszProgram_);
    csz.use();
    depth.bind(VEIL_TEX_DEPTH);
    glBindImageTexture(VEIL_IMG_OUTPUT, csz_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    dispatch(width_, height_);

    const gpu::Program& down = programs_.get(downsampleProgram_);
    down.use();
    csz_.bind(VEIL_TEX_AO_INPUT);
    for (int level = 0; level + 1 < levels_; ++level) {
        down.set("aoLevel", level);
        glBindImageTexture(VEIL_IMG_OUTPUT, csz_.id(), level + 1, GL_FALSE, 0, GL_WRITE_ONLY,
                           GL_R32F);
        dispatch(std::max(1, width_ >> (level + 1)), std::max(1, height_ >> (level + 1)));
    }

    const Properties& p = properties_;
    const gpu::Program& sao = programs_.get(saoProgram_);
    sao.use();
    sao.set("aoRadius", p.getFloat("radius"))
        .set("aoIntensity", p.getFloat("intensity"))
        .set("aoContrast", p.getFloat("contrast"))
        .set("aoBias", p.getFloat("bias"))
        .set("aoEpsilon", p.getFloat("epsilon"))
        .set("aoSamples", p.getInt("samples"))
        .set("aoTurns", p.getInt("spiral_turns"))
        .set("aoLevels", levels_);
    csz_.bind(VEIL_TEX_AO_INPUT);
    glBindImageTexture(VEIL_IMG_OUTPUT, raw_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
    dispatch(width_, height_);
}

void AmbientOcclusion::blur() const {
    const int radius = properties_.getInt("blur_radius");
    if (radius == 0) return;
    const gpu::Program& blur = programs_.get(blurProgram_);
    blur.use();
    blur.set("aoBlurRadius", radius)
        .set("aoStride", properties_.getInt("blur_stride"))
        .set("aoSharpness", properties_.getFloat("blur_sharpness"));
    csz_.bind(VEIL_TEX_AO_INPUT);
    const gpu::Texture* from[2] = {&raw_, &tmp_};
    const gpu::Texture* to[2] = {&tmp_, &blurred_};
    for (int axis = 0; axis < 2; ++axis) {
        blur.set("aoAxis", axis == 0 ? glm::ivec2(1, 0) : glm::ivec2(0, 1));
        from[axis]->bind(VEIL_TEX_AO_INPUT + 1);
        glBindImageTexture(VEIL_IMG_OUTPUT, to[axis]->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
        dispatch(width_, height_);
    }
}

const gpu::Texture& AmbientOcclusion::visibility() const {
    return properties_.getInt("blur_radius") > 0 ? blurred_ : raw_;
}

void AmbientOcclusion::resize(pass::Context& context) {
    resize(context.width, context.height);
    context.ambientOcclusion = &visibility();
}

std::vector<pass::Pass> AmbientOcclusion::passes(const pass::Assembly&) {
    return {{"ao",
             {"depth"},
             {"ao.depth", "ao.raw"},
             [this](const pass::Context& context) { estimate(*context.depth); }},
            {"ao.blur", {"ao.depth", "ao.raw"}, {"ao.visibility"}, [this](const pass::Context&) {
                 blur();
             }}};
}

void AmbientOcclusion::addResources(pass::Resources& resources) const {
    resources.add("ao.depth", [this] { return &csz_; });
    resources.add("ao.raw", [this] { return &raw_; });
    resources.add("ao.visibility", [this] { return &visibility(); });
}

std::size_t AmbientOcclusion::gpuBytes() const {
    const std::size_t pixels = std::size_t(width_) * height_;
    std::size_t bytes = pixels * 4 * 4 / 3 + pixels * 2; // z pyramid, raw
    if (properties_.getInt("blur_radius") > 0) bytes += 2 * pixels * 2;
    return bytes;
}

} // namespace veil::frame
