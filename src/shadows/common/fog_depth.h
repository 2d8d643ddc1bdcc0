// The grid density volumes' optical depth along every light view, for the shadow techniques
// whose maps hold no fog of their own (`transmittance-slicemap`, `stochastic`,
// `stochastic-vsm`): per view, `columns`^2 columns of the view, each marched from the near plane
// with `substeps` midpoint density samples per slice of `slices` uniform slices of the view's
// normalized linear depth, the cumulative optical depth stored at every slice boundary
// (shaders/shadows/common/fog_depth.comp). Receivers read exp(-tau) linearly between slice
// boundaries and bilinearly between columns (fog_depth.glsl), the deep shadow map of the media
// [Lokovic00]; surfaces and fog samples alike, so the fog marcher's own self-shadowing
// volumes are off while this is on (Technique::attenuatesMedia()). The samples of a column are
// marched in dispatches of kSamplesPerDispatch, within llvmpipe's loop limit.
#pragma once

#include "shadows/technique.h"

namespace veil::shadows {

class FogDepthMap {
public:
    FogDepthMap(gpu::ProgramManager& programs, int columns, int slices, int substeps);
    void resize(int mapSize, int views);
    // Marches the columns of the view rows [y0 C / size, y1 C / size) for the map rows
    // [y0, y1) (all: 0, size), so consecutive bands of map rows cover the columns once; does
    // nothing (and leaves the receivers' uniform off) without grid volumes in the frame.
    void run(const pass::Context& frame, int y0, int y1);
    // run() as the technique's light pass "fog" (writes shadow.fog), refinable in map rows.
    pass::Pass pass() {
        return {"fog",
                {},
                {"shadow.fog"},
                [this](const pass::Context& f) { run(f, 0, size_); },
                [this](const pass::Context& f, int y0, int y1) { run(f, y0, y1); }};
    }
    // The R32F volume at VEIL_TEX_SHADOW2 and the receiver's uniform shadowFog (1 when this
    // frame's volumes were marched); shadowFogSlices comes from the technique's params.
    void bind() const { tau_.bind(VEIL_TEX_SHADOW2); }
    void prepareReceiver(const gpu::Program& program) const;
    const gpu::Texture& texture() const { return tau_; }
    std::size_t gpuBytes() const {
        return std::size_t(columns_) * columns_ * (std::max(views_, 1) * (slices_ + 1) * 4 + 8);
    }
    int slices() const { return slices_; }
    Technique::WorkEstimate work(int viewCount, bool media) const;

    // Density samples per column and dispatch: Mesa's llvmpipe ends all loops of one shader
    // invocation after 65535 iterations (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS), and a column
    // takes fog_slices x fog_substeps samples (up to 65536), each up to about 8 iterations
    // with the volume slots' loop, plus up to 1025 boundary stores: 4096 x 8 + 1025 stay far
    // below the limit, and the defaults (128 x 4) need one dispatch.
    static constexpr int kSamplesPerDispatch = 4096;

private:
    gpu::ProgramManager& programs_;
    gpu::ProgramHandle program_;
    gpu::Texture tau_{gpu::NoCreate};
    gpu::Texture state_{gpu::NoCreate}; // RG32F per column: the sum so far, the next boundary
    int columns_, slices_, substeps_;
    int size_ = 0, views_ = 0;
    bool active_ = false;
};

// The properties of a technique that uses FogDepthMap: fog, fog_columns, fog_substeps (and
// fog_slices when `ownSlices`: techniques without slices of their own).
PropertySchema& addFogDepthProperties(PropertySchema& schema, bool ownSlices);

} // namespace veil::shadows
