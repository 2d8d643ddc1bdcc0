// The frame: an ordered list of stages (pass::Stage, src/pass/stage.h; built by
// frame::buildStages, frame_setup.h), whose declared passes (src/pass/pass.h) are concatenated
// into one list (frame/pass_list.h) with the resources each reads and writes, and run with
// per-pass GPU times. The stages, in order:
//   shadows       scope Lights: the shadow technique's passes (src/shadows), maps of every
//                 view of every shadow-casting light (only when a light casts shadows)
//   depth         with AO on: the opaque objects' depth alone (pre-pass)
//   ao            with AO on: ambient obscurance of that depth (`ao`, `ao.blur`)
//   opaque        forward shading into the HDR target with depth (ambient term times AO)
//   fog           scope Pixels: density volumes ray-marched per pixel (only with volumes)
//   transparency  scope Pixels: transparent surfaces (and the fog) through the OIT
//                 technique's oitEmit() (`transparent`), and its composite (`resolve`)
//   tonemap       exposure + operator + sRGB into the LDR target (compute)
// Every pass gets the same pass::Context; the name -> texture table of the resources
// (resourceTexture) is filled by the stage that writes each. The renderer only runs the list:
// another stage is inserted (insertStage), never written into it.
#pragma once

#include "fog/fog_pass.h"
#include "frame/frame_setup.h"
#include "frame/gpu_mesh.h"
#include "frame/pass_list.h"
#include "frame/refiner.h"
#include "frame/stages/compute_raster.h"
#include "gpu/context.h"
#include "gpu/pipeline_state.h"
#include "gpu/readback.h"
#include "gpu/shader.h"
#include "gpu/timer.h"
#include "oit/technique.h"
#include "scene/scene.h"
#include "shadows/technique.h"
#include "voxelize/light_slice_map.h"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace veil::volume {
struct GridConversion;
}

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
    static constexpr int kRefineShadowBandTexels = Refiner::kShadowBandTexels;
    static constexpr int kRefineLightSlabTexels = 8;
    int refineMarginPx() const;
    void beginRefinement(int tilePx);
    bool refineStep(int maxTilePx = 0);
    void cancelRefinement() { refiner_.cancel(); }
    bool refining() const { return refiner_.state().active; }
    using Refinement = frame::Refinement;
    const Refinement& refinement() const { return refiner_.state(); }
    // Times of the passes of the last render().
    const std::vector<gpu::PassTime>& passTimes() const { return passTimes_; }

    gpu::ImageF readHdr() const; // linear radiance, RGBA float, top row first
    // readHdr into a caller's width() * height() * 4 floats.
    void readHdrInto(float* pixels, std::size_t count) const;
    gpu::ImageF readLdr() const; // tone-mapped sRGB in [0,1], RGBA
    const gpu::Texture& hdrTexture() const { return targets_.hdr; }
    const gpu::Texture& ldrTexture() const { return targets_.ldr; }

    int width() const { return width_; }
    int height() const { return height_; }
    const std::string& oitName() const { return stages_.transparency->techniqueName(); }
    const oit::Technique& technique() const { return stages_.transparency->technique(); }
    const shadows::Technique& shadowTechnique() const { return stages_.shadows->technique(); }
    // Scene light indices that cast shadows, and the views of their maps (last frame's fit).
    const shadows::ShadowLightSet& shadowLights() const { return stages_.shadows->lights(); }
    const std::vector<shadows::LightView>& shadowViews() const { return stages_.shadows->views(); }
    const scene::Camera& camera() const { return camera_; }
    void setCamera(const scene::Camera& camera) { camera_ = camera; }
    gpu::GpuTimer::Mode timerMode() const { return timer_.mode(); }
    std::size_t gpuBytes() const;
    // The fog pass (density volumes); null when the scene has no volumes.
    const volume::FogPass* fog() const { return stages_.fog ? &stages_.fog->fog() : nullptr; }
    // Keep the fog's per-pixel march (frame resource fog.radiance) under a technique that takes
    // the fog piecewise (`reference`), for a reader of it (--aov fog, --dump); otherwise it is
    // skipped there (FogPass::perPixelMarchRuns()).
    void keepFogRadiance(bool on) {
        if (stages_.fog) stages_.fog->fog().keepPerPixelMarch(on);
    }
    // The next frame recomputes the fog's light transmittance volumes (veil-bench --relight).
    void invalidateFogLightVolumes() {
        if (stages_.fog) stages_.fog->fog().invalidateLightVolumes();
    }
    // The fog's scattered-light cache bakes at most `ms` per frame on the GPU, converging over
    // frames (the viewer); 0, the default, bakes it to the end before the frame.
    void setScatteredLightBudgetMs(double ms) {
        if (stages_.fog) stages_.fog->fog().setScatteredLightBudgetMs(ms);
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
        reuse().enabled = on;
        reuse().valid = false;
    }
    bool reusesShadowMaps() const { return stages_.shadows->reuse().enabled; }
    void invalidateShadowMaps() { reuse().valid = false; }
    bool shadowMapsValid() const { return stages_.shadows->reuse().valid; }
    // Frames (render(), beginRefinement()) that ran the shadow passes, and that skipped them
    // keeping the last maps.
    std::uint64_t shadowMapRenders() const { return stages_.shadows->reuse().renders; }
    std::uint64_t shadowMapReuses() const { return stages_.shadows->reuse().reuses; }
    // The screen-space AO pass; null when render.ao.enabled is false.
    const AmbientOcclusion* ambientOcclusion() const { return stages_.ao; }
    // The frame's passes in order, with the resources each reads and writes.
    const PassList& passes() const { return passes_; }
    // The texture behind a frame resource (the table the modules fill: depth, hdr, ldr,
    // shadow.* arrays with one layer per light view, ao.*, fog.*, oit.<technique>.*), or null
    // when it has none now (fog.radiance where the march skips it).
    const gpu::Texture* resourceTexture(const std::string& name) const;
    // Recompiles every shader from disk; failing programs keep their previous version (their
    // messages go to `errors` when given).
    int reloadShaders(std::vector<std::string>* errors = nullptr) {
        invalidateShadowMaps(); // the shadow passes' programs may have changed
        return programs_.reloadAll(errors);
    }
    // Programs that exist now (tests: a technique switch releases the old technique's).
    std::size_t liveProgramCount() const { return programs_.liveCount(); }

    // Changes that rebuild only what depends on them (the viewer; derived structures are rebuilt
    // when what they depend on changed): Another OIT technique (or other property values): a
    // new transparency stage (the technique, its transparent and fog-emission programs and its
    // targets) built aside and swapped in whole, releasing the old one's programs; the pass
    // list is rebuilt with the new technique's resources. Meshes, volumes, shadow maps stay.
    // Throws veil::Error (unknown, unavailable, bad property, shader) and then changes nothing.
    void setOitTechnique(const std::string& name, const nlohmann::json& properties,
                         const std::string& where = "OIT properties");
    // Another frame size: the frame targets and the stages'; the fog resizes its own.
    void resize(int width, int height);
    // The scene's volume or light values changed in place (density scale, albedo, a light
    // moved): the fog's light transmittance volumes are recomputed at the next frame.
    void sceneValuesChanged();

    // Frame ranges (sequence/range_render.h): the scene this renderer was built on now holds
    // another frame, changed in place (other volume files, camera and light values; the same
    // objects, lights, volumes and settings). Grid volume i (scene order, homogeneous fog
    // skipped) takes the data of `converted[i]`, made as the fog pass would make it; the camera
    // becomes the scene's `camera` (empty: render.camera); the shadow views follow the new
    // bounds; light transmittance volumes and shadow maps are recomputed. Programs, targets and
    // the other stages stay. Throws veil::Error when the counts differ or a conversion does not
    // fit its volume.
    void replaceVolumes(const std::vector<const volume::GridConversion*>& converted,
                        const std::string& camera);
    // replaceVolumes() in two steps, so that the next frame's upload overlaps this frame's
    // render: uploadVolumes() after render() and before the image is read back (the copies
    // queue behind the frame's commands; the scene's volume entries already hold the next
    // frame's), then showUploaded() before the next render(): the camera, the shadow bounds
    // and the recomputation of the light volumes and shadow maps.
    void uploadVolumes(const std::vector<const volume::GridConversion*>& converted);
    void showUploaded(const std::string& camera);

    // The stages in frame order, by name ("shadows", "depth", "ao", "opaque", "fog",
    // "transparency", "tonemap"; docs/architecture.md "Adding a stage" shows how to write one).
    std::vector<std::string> stageNames() const;
    // Inserts the stage `make` builds (with the renderer's programs) before the stage named
    // `before` and rebuilds the pass list. Throws veil::Error (no such stage; the new list does
    // not validate) and then keeps the stages it had.
    using StageFactory = std::function<std::unique_ptr<pass::Stage>(gpu::ProgramManager&)>;
    void insertStage(const StageFactory& make, const std::string& before);

private:
    friend class Refiner;
    struct Targets {
        gpu::Texture hdr{gpu::NoCreate}, depth{gpu::NoCreate}, ldr{gpu::NoCreate};
    };
    ShadowStage::Reuse& reuse() { return stages_.shadows->reuse(); }
    void createTargets();
    void buildPasses();
    void rebuildPasses();
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
    gpu::ProgramManager programs_; // before the stages: they release their programs into it
    std::vector<GpuMesh> meshes_;
    FrameStages stages_;
    gpu::Buffer cameraUbo_, lightsUbo_;
    Targets targets_;
    pass::Context pass_; // what every pass gets
    pass::Resources resources_;
    PassList passes_;
    gpu::StateTracker state_; // every pass's fixed-function state goes through it
    gpu::GpuTimer timer_;
    std::vector<gpu::PassTime> passTimes_;
    Refiner refiner_{*this};
};

} // namespace veil::frame
