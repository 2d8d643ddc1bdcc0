// The frame: the passes the modules declare (src/pass/pass.h), concatenated in order into one
// list (frame/pass_list.h) with the resources each reads and writes, and per-pass GPU times:
//   shadow[.*]  scope Lights: the shadow technique's passes (src/shadows), maps of every view
//               of every shadow-casting light (only when a light casts shadows)
//   depth       with AO on: the opaque objects' depth alone (pre-pass)
//   ao, ao.blur with AO on: ambient obscurance of that depth (frame/ambient_occlusion.h)
//   opaque      forward shading into the HDR target with depth (ambient term times AO)
//   fog         scope Pixels: density volumes ray-marched per pixel (volume::FogPass; only
//               with volumes)
//   transparent scope Pixels: transparent surfaces (and the fog) through the OIT technique's
//               oitEmit() (oit::Technique::passes, frame/transparency.h)
//   resolve     the technique's composite over the opaque image
//   tonemap     exposure + operator + sRGB into the LDR target (compute)
// Every pass gets the same pass::Context; the name -> texture table of the resources
// (resourceTexture) is filled by the module that writes each.
#pragma once

#include "frame/ambient_occlusion.h"
#include "frame/gpu_mesh.h"
#include "frame/pass_list.h"
#include "frame/refinement.h"
#include "frame/renderer_setup.h"
#include "frame/transparency.h"
#include "gpu/context.h"
#include "gpu/pipeline_state.h"
#include "gpu/readback.h"
#include "gpu/shader.h"
#include "gpu/timer.h"
#include "oit/compute_raster/compute_raster.h"
#include "oit/technique.h"
#include "scene/scene.h"
#include "shadows/technique.h"
#include "volume/fog_pass.h"
#include "voxelize/light_slice_map.h"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace veil::frame {

class Renderer {
public:
    Renderer(const scene::Scene& scene, const gpu::ContextInfo& context,
             const RendererOptions& options = {});
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    void render();

    // Progressive refinement (frame/refinement.h has what the calls do): the same frame as
    // render(), bit for bit, split over calls to refineStep() until it returns true.
    static constexpr int kRefineShadowBandTexels = 131072; // 64 rows of a 2048^2 map
    static constexpr int kRefineLightSlabTexels = 8;
    int refineMarginPx() const;
    void beginRefinement(int tilePx);
    bool refineStep(int maxTilePx = 0);
    void cancelRefinement() { refine_.active = false; }
    bool refining() const { return refine_.active; }
    using Refinement = frame::Refinement;
    const Refinement& refinement() const { return refine_; }
    // Times of the passes of the last render().
    const std::vector<gpu::PassTime>& passTimes() const { return passTimes_; }

    gpu::ImageF readHdr() const; // linear radiance, RGBA float, top row first
    // readHdr into a caller's width() * height() * 4 floats.
    void readHdrInto(float* pixels, std::size_t count) const;
    gpu::ImageF readLdr() const; // tone-mapped sRGB in [0,1], RGBA
    const gpu::Texture& hdrTexture() const { return hdr_; }
    const gpu::Texture& ldrTexture() const { return ldr_; }

    int width() const { return width_; }
    int height() const { return height_; }
    const std::string& oitName() const { return oitName_; }
    const oit::Technique& technique() const { return *oit_; }
    const shadows::Technique& shadowTechnique() const { return *shadows_; }
    // Scene light indices that cast shadows, and the views of their maps (last frame's fit).
    const shadows::ShadowLightSet& shadowLights() const { return shadowSet_; }
    const std::vector<shadows::LightView>& shadowViews() const { return shadowViews_; }
    const scene::Camera& camera() const { return camera_; }
    void setCamera(const scene::Camera& camera) { camera_ = camera; }
    gpu::GpuTimer::Mode timerMode() const { return timer_.mode(); }
    std::size_t gpuBytes() const;
    // The fog pass (density volumes); null when the scene has no volumes.
    const volume::FogPass* fog() const { return fog_.get(); }
    // Keep the fog's per-pixel march (frame resource fog.radiance) under a technique that takes
    // the fog piecewise (`reference`), for a reader of it (--aov fog, --dump); otherwise it is
    // skipped there (FogPass::perPixelMarchRuns()).
    void keepFogRadiance(bool on) {
        if (fog_) fog_->keepPerPixelMarch(on);
    }
    // The next frame recomputes the fog's light transmittance volumes (veil-bench --relight).
    void invalidateFogLightVolumes() {
        if (fog_) fog_->invalidateLightVolumes();
    }
    // Shadow map reuse (the viewer, docs/viewer.md "Slow drivers"): with it on and a shadow
    // technique whose maps do not depend on the camera (shadows::Technique::dependsOnCamera),
    // a frame skips the shadow passes when the maps of an earlier frame are still valid. They
    // become invalid on every change that can alter them: a new renderer (scene, shadow
    // technique or its properties, objects, meshes: the viewer rebuilds the renderer),
    // sceneValuesChanged() (lights, volume values), invalidateShadowMaps() (materials and any
    // other in-place edit), reloadShaders(), and turning reuse on. A frame size change keeps
    // them (the maps have their own size; a camera-dependent technique redraws anyway), and so
    // does another OIT technique.
    void setReuseShadowMaps(bool on) {
        reuseShadowMaps_ = on;
        shadowMapsValid_ = false;
    }
    bool reusesShadowMaps() const { return reuseShadowMaps_; }
    void invalidateShadowMaps() { shadowMapsValid_ = false; }
    bool shadowMapsValid() const { return shadowMapsValid_; }
    // Frames (render(), beginRefinement()) that ran the shadow passes, and that skipped them
    // keeping the last maps.
    std::uint64_t shadowMapRenders() const { return shadowMapRenders_; }
    std::uint64_t shadowMapReuses() const { return shadowMapReuses_; }
    // The screen-space AO pass; null when render.ao.enabled is false.
    const AmbientOcclusion* ambientOcclusion() const { return ao_.get(); }
    const Properties& aoProperties() const { return aoProperties_; }
    // The frame's passes in order, with the resources each reads and writes.
    const PassList& passes() const { return passes_; }
    // The texture behind a frame resource (the table the modules fill: depth, hdr, ldr,
    // shadow.* arrays with one layer per light view, ao.*, fog.*, oit.<technique>.*), or null
    // when it has none now (fog.radiance where the march skips it).
    const gpu::Texture* resourceTexture(const std::string& name) const;
    // Recompiles every shader from disk; failing programs keep their previous version (their
    // messages go to `errors` when given).
    int reloadShaders(std::vector<std::string>* errors = nullptr) {
        shadowMapsValid_ = false; // the shadow passes' programs may have changed
        return programs_.reloadAll(errors);
    }
    // Programs that exist now (tests: a technique switch releases the old technique's).
    std::size_t liveProgramCount() const { return programs_.liveCount(); }

    // Changes that rebuild only what depends on them (the viewer; derived structures are rebuilt
    // when what they depend on changed): Another OIT technique (or other property values): the
    // technique, its transparent and fog-emission programs and its targets (the old technique's
    // programs are deleted; the pass list is rebuilt with the new technique's resources). Meshes,
    // volumes, shadow maps stay. Throws veil::Error (unknown, unavailable, bad property, shader)
    // and then changes nothing.
    void setOitTechnique(const std::string& name, const nlohmann::json& properties,
                         const std::string& where = "OIT properties");
    // Another frame size: the frame targets and the technique's; the fog resizes its own.
    void resize(int width, int height);
    // The scene's volume or light values changed in place (density scale, albedo, a light
    // moved): the fog's light transmittance volumes are recomputed at the next frame.
    void sceneValuesChanged();

private:
    void createTargets();
    void buildPasses();
    void rebuildPasses();
    void addPass(pass::Pass p);
    void opaque(bool depthOnly);
    void updateUniforms();
    void beginFrame();
    void bindFrameState();
    void setRegion(glm::ivec4 region); // the Pixels passes' pixels (and opaqueColor)
    bool hasLightPasses() const;
    void runPass(const pass::Pass& p);
    void runPasses(pass::Scope scope);
    void runLightPasses(); // unless kept by the shadow map reuse

    const scene::Scene& scene_;
    gpu::ContextInfo context_;
    scene::Camera camera_;
    int width_ = 0, height_ = 0;
    std::string oitName_;
    glm::vec3 boundsLo_{0.0f}, boundsHi_{0.0f};

    gpu::ProgramManager programs_;
    gpu::ProgramHandle opaqueProgram_, tonemapProgram_;
    TransparencyPrograms transparency_;
    std::unique_ptr<volume::FogPass> fog_;
    Properties aoProperties_;
    std::unique_ptr<AmbientOcclusion> ao_;
    std::vector<GpuMesh> meshes_;
    std::unique_ptr<oit::Technique> oit_;
    // The transparent pass's compute rasterizer (render.oit_rasterizer = compute), else null.
    std::unique_ptr<oit::ComputeRaster> computeRaster_;
    std::unique_ptr<oit::ComputeRaster> makeComputeRaster();
    // Every program the OIT technique brought (its own, transparent, fog emission, fog
    // segments): released when setOitTechnique() replaces it.
    std::vector<gpu::ProgramHandle> oitPrograms_;
    std::unique_ptr<shadows::Technique> shadows_;
    // The light slice map the shadow technique asks for (its voxelize pass), or null.
    std::unique_ptr<voxelize::LightSliceMap> lightSlices_;
    shadows::ShadowLightSet shadowSet_;
    std::vector<shadows::LightView> shadowViews_;
    std::vector<std::string> shadowResources_; // what receivers read
    int shadowMapSize_ = 0;

    gpu::Buffer cameraUbo_{gpu::NoCreate}, lightsUbo_{gpu::NoCreate}, shadowsUbo_{gpu::NoCreate};
    gpu::Texture hdr_{gpu::NoCreate}, depth_{gpu::NoCreate}, ldr_{gpu::NoCreate};
    gpu::Framebuffer opaqueFbo_{gpu::NoCreate};
    pass::Context pass_; // what every pass gets
    pass::Resources resources_;
    PassList passes_;
    bool reuseShadowMaps_ = false;
    bool shadowMapsValid_ = false;  // the maps hold what the shadow passes would draw now
    bool skipShadowPasses_ = false; // this frame's decision (beginFrame())
    std::uint64_t shadowMapRenders_ = 0, shadowMapReuses_ = 0;
    Refinement refine_;
    void runPerFramePasses(bool lights); // (Lights and) Frame passes, then keep opaque
    void refineShadowStep();             // one band or unbanded pass of the shadow maps
    gpu::Texture opaqueHdr_{gpu::NoCreate}, refinedHdr_{gpu::NoCreate}, refinedLdr_{gpu::NoCreate};
    gpu::StateTracker state_; // every pass's fixed-function state goes through it
    gpu::GpuTimer timer_;
    std::vector<gpu::PassTime> passTimes_;
};

} // namespace veil::frame
