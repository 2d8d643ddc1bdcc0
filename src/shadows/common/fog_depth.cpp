#include "shadows/common/fog_depth.h"

#include "shaders/common/bindings.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>

namespace veil::shadows {

FogDepthMap::FogDepthMap(gpu::ProgramManager& programs, int columns, int slices, int substeps)
    : programs_(programs), columns_(columns), slices_(slices), substeps_(substeps) {
    program_ = programs.add(gpu::ProgramDesc::compute("shadows/common/fog_depth.comp"));
}

void FogDepthMap::resize(int mapSize, int views) {
    if (mapSize == size_ && views == views_) return;
    size_ = mapSize;
    views_ = views;
    state_ = gpu::Texture(GL_TEXTURE_2D);
    state_.storage2D(1, GL_RG32F, columns_, columns_);
    tau_ = gpu::Texture(GL_TEXTURE_3D);
    tau_.storage3D(1, GL_R32F, columns_, columns_, std::max(views_, 1) * (slices_ + 1))
        .parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
}

void FogDepthMap::run(const pass::Context& frame, int y0, int y1) {
    active_ = static_cast<bool>(frame.bindMedia);
    if (!active_) return;
    const int c0 = int(std::int64_t(y0) * columns_ / size_);
    const int c1 = int(std::int64_t(y1) * columns_ / size_);
    if (c0 >= c1) return;
    frame.state->apply(gpu::PipelineState{}); // compute only
    const gpu::Program& p = programs_.get(program_);
    p.use();
    frame.bindMedia(p);
    glBindImageTexture(VEIL_IMG_VOLUME_LIGHT, tau_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R32F);
    glBindImageTexture(VEIL_IMG_VOLUME_LIGHT_STATE, state_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                       GL_RG32F);
    const int samples = slices_ * substeps_;
    for (const LightView& view : *frame.lightViews) {
        p.set("shadowView", view.layer)
            .set("uSlices", slices_)
            .set("uSubsteps", substeps_)
            .set("uColumns", columns_)
            .set("uClipToWorld", glm::inverse(view.viewProjection))
            .set("rows", glm::ivec2(c0, c1));
        // Each column's samples in dispatches of at most kSamplesPerDispatch, the sum carried
        // in state_ from one to the next (fog_depth.comp).
        for (int m0 = 0; m0 < samples; m0 += kSamplesPerDispatch) {
            if (m0 > 0) glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            p.set("uSamples", glm::ivec2(m0, std::min(samples, m0 + kSamplesPerDispatch)));
            glDispatchCompute((columns_ + 7) / 8, (c1 - c0 + 7) / 8, 1);
        }
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT); // state_ again for the next view
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glUseProgram(0);
}

void FogDepthMap::prepareReceiver(const gpu::Program& program) const {
    program.set("shadowFog", active_ ? 1 : 0).set("shadowFogSlices", slices_);
}

Technique::WorkEstimate FogDepthMap::work(int viewCount, bool media) const {
    if (!media) return {};
    const double views = std::max(viewCount, 1);
    return {double(columns_) * columns_ * views * (slices_ + 1) * substeps_,
            fmt::format("fog optical depth: {}^2 columns (fog_columns) x {} view(s) x {} "
                        "slices (slices + 1) x {} substeps (fog_substeps)",
                        columns_, viewCount, slices_ + 1, substeps_)};
}

PropertySchema& addFogDepthProperties(PropertySchema& schema, bool ownSlices) {
    schema.boolean("fog", true,
                   "the grid density volumes attenuate receivers through a per-slice optical "
                   "depth along the light view's columns (a compute pass; the fog marcher's own "
                   "self-shadowing volumes are then off); false: the marcher self-shadows and "
                   "surfaces get no fog shadow",
                   "[Lokovic00] (deep shadow maps of the media)");
    schema.integer("fog_columns", 128, 4, 4096,
                   "fog columns per side of each light view (optical depth is bilinear between "
                   "them)");
    if (ownSlices)
        schema.integer("fog_slices", 128, 1, 1024,
                       "uniform slices of the light view's depth for the fog's optical depth "
                       "(linear between slice boundaries)");
    schema.integer("fog_substeps", 4, 1, 64,
                   "midpoint density samples per slice of the fog's optical depth (error of a "
                   "density edge: sigma x slice length / substeps)");
    return schema;
}

} // namespace veil::shadows
