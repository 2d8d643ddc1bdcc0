// Screen-space ambient obscurance of the opaque depth buffer: the frame's AO buffer, read by
// the opaque shading (its ambient term times AO) and by OIT techniques that infer AO at
// partial coverage (phenomenological, [McGuire17 sec. 6 / Listing 2]).
//
// Estimator: Scalable Ambient Obscurance (McGuire, Mara & Luebke, HPG 2012; [McGuire17] cites the
// family as [32]), written from its published description (shaders/frame/ao/sao.comp):
//   A(C) = max(0, 1 - (2 sigma / s) sum_i H(r^2 - |v_i|^2) max(0, v_i.n - beta z_C)
//                                        / (|v_i|^2 + epsilon))^k
// with s spiral samples in screen space read from a camera-space z pyramid, then a
// separable bilateral blur. Properties (render.ao.KEY; defaults in brackets):
//   enabled       [false] the AO pass and the opaque pass's AO (off: the frame as before)
//   radius        [0.5]   r, world (view-space) units of the sampled hemisphere
//   intensity     [1]     sigma
//   contrast      [1]     k (sharpness of the falloff to black)
//   bias          [0.01]  beta, scaled by the view distance z_C (self-occlusion of facets)
//   epsilon       [0.01]  epsilon of the denominator (SAO: 0.01)
//   samples       [11]    s
//   spiral_turns  [7]     tau (SAO picks tau per s so that samples do not line up)
//   mip_levels    [5]     levels of the z pyramid (1 = every sample at full resolution)
//   blur_radius   [4]     R taps each side per axis (0 = no blur)
//   blur_stride   [2]     pixels between taps
//   blur_sharpness [20]   depth weight max(0, 1 - sharpness |dz| / z)
// What differs from SAO: the per-pixel spiral rotation comes from an integer hash (the CPU
// reference reproduces it exactly); a sample read from pyramid level m is placed at the pixel
// its z came from (SAO places it at the sample's own pixel, off the surface by the depth slope
// across the 2^m block: false occlusion on grazing floors); the normal comes from the z pyramid's
// neighbours (the closer of the two on each axis) instead of derivatives in a G-buffer pass; z is
// stored as 32-bit float, not packed with AO for the blur.
//
// With AO on, the frame draws the opaque objects twice: a depth pre-pass (`depth`), the AO
// passes (`ao`, `ao.blur`) over it, then the shaded opaque pass testing GL_LEQUAL.
#pragma once

#include "base/properties.h"
#include "gpu/objects.h"
#include "gpu/shader.h"
#include "pass/stage.h"

#include <string>
#include <vector>

namespace veil::frame {

class AmbientOcclusion : public pass::Stage {
public:
    static const PropertySchema& schema();

    AmbientOcclusion(gpu::ProgramManager& programs, Properties properties);
    bool enabled() const { return properties_.getBool("enabled"); }
    const Properties& properties() const { return properties_; }

    void resize(int width, int height);
    // csz + pyramid + estimator, from the opaque depth (window depth) of the frame; the
    // camera UBO must be bound.
    void estimate(const gpu::Texture& depth) const;
    void blur() const; // no-op with blur_radius 0
    // The ambient visibility every receiver reads (blurred, or raw without blur).
    const gpu::Texture& visibility() const;
    // The stage `ao`: the passes `ao` (estimate() from the context's depth: writes ao.depth,
    // the z pyramid, and ao.raw) and `ao.blur` (writes ao.visibility), scope Frame, and their
    // resources; the context's ambientOcclusion is the visibility.
    std::string name() const override { return "ao"; }
    std::vector<pass::Pass> passes(const pass::Assembly& assembly) override;
    void addResources(pass::Resources& resources) const override;
    std::size_t gpuBytes() const override;
    void resize(pass::Context& context) override;
    int levels() const { return levels_; }

private:
    gpu::ProgramManager& programs_;
    Properties properties_;
    gpu::ProgramHandle cszProgram_, downsampleProgram_, saoProgram_, blurProgram_;
    int width_ = 0, height_ = 0, levels_ = 1;
    gpu::Texture csz_{gpu::NoCreate}, raw_{gpu::NoCreate}, tmp_{gpu::NoCreate},
        blurred_{gpu::NoCreate};
};

} // namespace veil::frame
