// The frame's transparency stage: the OIT technique (src/oit) with the programs that join it
// to the frame. Its passes are the technique's (oit::Technique::passes: `transparent` and
// `resolve`, or the compute rasterizer's stages with render.oit_rasterizer = compute,
// compute_raster.h) with these hooks: the transparent-surface programs (one per geometry pass,
// with the technique's emit include), the fog's contribution through the same oitEmit()
// before the surfaces (shaders/volume/fog_emit.*: compute where the technique writes its
// targets as images, oit::PerPixelEmit, else a full-screen fragment), or, for a technique with
// fogSegments() (`reference`), the fog marched piecewise between its stored surfaces after the
// last geometry pass (fog_segments.comp).
//
// The stage owns every program it brought (the technique's own too) and releases them when
// it goes: choosing another OIT technique builds a new stage aside and swaps it in whole
// (frame::Renderer::setOitTechnique); the fog pass is only told, when the frame assembles its
// passes, whether its per-pixel march has a reader (volume::FogPass::setPiecewise).
#pragma once

#include "fog/fog_pass.h"
#include "frame/stages/compute_raster.h"
#include "gpu/context.h"
#include "gpu/shader.h"
#include "oit/technique.h"
#include "pass/stage.h"
#include "scene/scene.h"
#include "shadows/technique.h"

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace veil::frame {

class TransparencyStage : public pass::Stage {
public:
    // Builds the stage from the technique `make` creates (its programs are the stage's), the
    // fog (null: none) and the shadow technique's receivers (its "veil:light_visibility"
    // include and receiver defines). On an exception every program added since the call is
    // released again.
    static std::unique_ptr<TransparencyStage>
    create(const std::function<std::unique_ptr<oit::Technique>()>& make, const scene::Scene& scene,
           gpu::ProgramManager& programs, volume::FogPass* fog,
           const shadows::Technique::Receivers& receivers);
    // Takes the technique built earlier (`techniquePrograms`: the programs it added) and adds
    // the rest; the same release on an exception.
    static std::unique_ptr<TransparencyStage>
    create(std::unique_ptr<oit::Technique> technique,
           std::vector<gpu::ProgramHandle> techniquePrograms, const scene::Scene& scene,
           gpu::ProgramManager& programs, volume::FogPass* fog,
           const shadows::Technique::Receivers& receivers);
    ~TransparencyStage() override;

    std::string name() const override { return "transparency"; }
    std::vector<pass::Pass> passes(const pass::Assembly& assembly) override;
    void addResources(pass::Resources& resources) const override;
    std::size_t gpuBytes() const override;
    void resize(pass::Context& context) override;

    const std::string& techniqueName() const { return name_; }
    const oit::Technique& technique() const { return *technique_; }

private:
    TransparencyStage(std::unique_ptr<oit::Technique> technique, gpu::ProgramManager& programs,
                      volume::FogPass* fog);
    void build(const scene::Scene& scene, const shadows::Technique::Receivers& receivers);
    void emitFog(const pass::Context& context, int pass) const;

    gpu::ProgramManager& programs_;
    std::unique_ptr<oit::Technique> technique_;
    std::string name_;
    volume::FogPass* fog_;
    std::vector<gpu::ProgramHandle> surface_; // one per geometry pass
    std::vector<gpu::ProgramHandle> fogEmit_; // one per geometry pass with fog (empty: none)
    gpu::ProgramHandle segments_;             // the piecewise fog march, for fogSegments()
    std::unique_ptr<ComputeRaster> raster_;   // render.oit_rasterizer = compute, else null
    std::vector<gpu::ProgramHandle> owned_;   // released with the stage
    std::size_t pixels_ = 0;
};

} // namespace veil::frame
