// The frame's fog stage: the density volumes ray-marched per pixel (volume::FogPass, pass
// `fog`, scope Pixels, a receiver of the shadow technique), with the light transmittance
// volumes as its prepare step for the tiled refinement (`slabTexels` z slices a step). Passes
// that sample the media (shadow techniques) get them through pass::Context::bindMedia.
#pragma once

#include "fog/fog_pass.h"
#include "pass/stage.h"

#include <memory>

namespace veil::frame {

// The define of the surface programs (opaque, transparent, compute-raster fine) of a frame
// whose fog has a scattered-light cache: their diffuse lobe receives the cache's light
// (shaders/volume/scattered_light.glsl). Frames without a cache compile without it.
inline constexpr const char* kSurfaceScatteredLightDefine = "VEIL_SURFACE_SCATTERED_LIGHT 1";

class FogStage : public pass::Stage {
public:
    FogStage(std::unique_ptr<volume::FogPass> fog, int slabTexels)
        : fog_(std::move(fog)), slabTexels_(slabTexels) {}

    std::string name() const override { return "fog"; }
    std::vector<pass::Pass> passes(const pass::Assembly&) override {
        return fog_->passes(slabTexels_);
    }
    void addResources(pass::Resources& resources) const override { fog_->addResources(resources); }
    std::size_t gpuBytes() const override { return fog_->gpuBytes(); }
    // Bakes the scattered-light cache if it is stale (not part of the timed pass `fog`), gives
    // receivers its textures and passes that sample the media the volumes.
    void beginFrame(pass::Context& context) override;

    volume::FogPass& fog() { return *fog_; }
    const volume::FogPass& fog() const { return *fog_; }

private:
    std::unique_ptr<volume::FogPass> fog_;
    int slabTexels_;
};

} // namespace veil::frame
