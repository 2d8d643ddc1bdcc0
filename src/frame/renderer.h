// The frame: an ordered list of passes (frame/pass_list.h) built from the scene, with the
// resources each reads and writes and per-pass GPU times (DESIGN.md "One frame"):
//   shadow[.*]  the shadow technique's passes (src/shadows): maps of every view of every
//               shadow-casting light (only when a light casts shadows)
//   depth       with AO on: the opaque objects' depth alone (pre-pass)
//   ao, ao.blur with AO on: ambient obscurance of that depth (frame/ambient_occlusion.h)
//   opaque      forward shading into the HDR target with depth (ambient term times AO)
//   fog         density volumes ray-marched per pixel (compute; only with volumes)
//   transparent transparent surfaces through the active OIT technique's oitEmit()
//   resolve     the technique's composite over the opaque image
//   tonemap     exposure + operator + sRGB into the LDR target (compute)
#pragma once

#include "frame/ambient_occlusion.h"
#include "frame/gpu_mesh.h"
#include "frame/pass_list.h"
#include "gpu/context.h"
#include "gpu/pipeline_state.h"
#include "gpu/readback.h"
#include "gpu/shader.h"
#include "gpu/timer.h"
#include "oit/technique.h"
#include "scene/scene.h"
#include "shadows/technique.h"
#include "volume/fog_pass.h"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace veil::frame {

struct RendererOptions {
    RendererOptions(int width_ = 0, int height_ = 0, std::string camera_ = {},
                    std::string oit_ = {}, nlohmann::json oitProperties_ = {},
                    std::string shadows_ = {}, nlohmann::json shadowProperties_ = {})
        : width(width_), height(height_), camera(std::move(camera_)), oit(std::move(oit_)),
          oitProperties(std::move(oitProperties_)), shadows(std::move(shadows_)),
          shadowProperties(std::move(shadowProperties_)) {}
    int width = 0;      // 0 = the scene's render.width
    int height = 0;     // 0 = the scene's render.height
    std::string camera; // empty = the scene's render.camera
    std::string oit;    // empty = the scene's render.oit
    // The technique's properties (a JSON object, see `veil techniques`). Null = the scene's
    // render.oit properties when the technique is the scene's, else the defaults.
    nlohmann::json oitProperties;
    std::string shadows; // empty = the scene's render.shadows
    // As oitProperties, for the shadow technique (null = the scene's when it is the scene's).
    nlohmann::json shadowProperties;
    // Keep the shadow technique's maps from the last frame while nothing they depend on
    // changed (Renderer::setReuseShadowMaps). Off for one-shot frames (`veil render`,
    // veil-bench: every frame draws its maps, so pass times stay honest); the viewer turns it
    // on (view.reuse_shadow_maps).
    bool reuseShadowMaps = false;
};

class Renderer {
public:
    Renderer(const scene::Scene& scene, const gpu::ContextInfo& context,
             const RendererOptions& options = {});
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    void render();

    // Progressive refinement (the viewer on slow drivers, docs/viewer.md "Slow drivers"): the
    // same frame as render(), bit for bit, split over several calls so that none takes much
    // longer than the frame's per-pixel passes over one tile. beginRefinement() runs the
    // per-frame passes (shadow maps, AO, opaque) once; while the fog's light transmittance
    // volumes are not valid each refineStep() computes kRefineLightSlabTexels z slices of one
    // of them (FogPass::updateLightVolumesSlab); then each refineStep() runs the per-pixel passes
    // (fog march, transparent, resolve, tonemap) for the next screen tile plus refineMarginPx()
    // around it (the OIT technique's: what its resolve reads around a pixel; scissor box of the
    // state tracker, region of the compute dispatches; the fog marches the texels its
    // upsampling reads) and keeps the tile; it returns true once every tile is done, and the
    // frame targets then hold the frame. The tiles: the frame's tilePx x tilePx grid in rows
    // from the top left; a step given maxTilePx > 0 first halves the next tile (in each side
    // over maxTilePx, quadrants in the same order) until it fits, so the caller can shrink the
    // work of a step when a step took too long (the viewer's time budget, app/view_session.h).
    // Until then hdrTexture()/ldrTexture() hold partial work: show the last complete image.
    // The camera and scene must not change between the calls (begin again instead: that
    // cancels). The OIT technique's resolve and compute passes run over the region too
    // (oit::OitFrameTargets::region; hdr outside it keeps earlier tiles' work), and so does
    // the copy of the opaque image into hdr that each tile starts from.
    int refineMarginPx() const;
    // When the shadow maps are to be drawn (not kept by reuse) and the shadow technique has
    // passes in bands of rows (shadows::ShadowPass::executeRows), the first steps draw them:
    // beginRefinement() only begins the frame, then each refineStep() runs one band of
    // about kRefineShadowBandTexels texels per map layer (rows = that / map size) of a banded
    // pass, or one unbanded pass whole; then one step runs the other per-frame passes (AO,
    // opaque); then the light slabs and the tiles follow.
    static constexpr int kRefineShadowBandTexels = 131072; // 64 rows of a 2048^2 map
    static constexpr int kRefineLightSlabTexels = 8;
    void beginRefinement(int tilePx);
    bool refineStep(int maxTilePx = 0);
    void cancelRefinement() { refine_.active = false; }
    bool refining() const { return refine_.active; }
    struct Refinement {
        bool active = false;
        int tilePx = 0, columns = 0, tiles = 0; // the grid: tiles = columns x rows
        int done = 0;                           // tile steps run (a split tile counts its parts)
        long long pixels = 0, pixelsDone = 0;   // of the frame, and in the tiles done
        glm::ivec4 lastTile{0};                 // pixels kept by the last tile step, x0 y0 x1 y1
        glm::ivec4 lastRegion{0}; // pixels of the last tile's per-pixel passes (tile + margin)
        // What the last refineStep() ran.
        enum class Step { None, ShadowBand, PerFrame, LightSlab, Tile } lastStep = Step::None;
        int lightSlabs = 0;  // light transmittance slabs computed by refineStep()
        int shadowSteps = 0; // shadow bands (and unbanded shadow passes) run by refineStep()
        // The shadow passes in progress: the next pass (-1: none left) and its next row; the
        // per-frame passes after them still to run.
        int shadowPass = -1, shadowRow = 0;
        bool perFramePending = false;
        // The tiles left, the next one last.
        std::vector<glm::ivec4> pending;
    };
    const Refinement& refinement() const { return refine_; }
    // Times of the passes of the last render().
    const std::vector<gpu::PassTime>& passTimes() const { return passTimes_; }

    gpu::ImageF readHdr() const; // linear radiance, RGBA float, top row first
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
    // The texture behind a frame resource (depth, hdr, ldr, shadow.* of the shadow technique:
    // arrays with one layer per light view, fog.radiance, fog.light_transmittance of the first
    // volume, oit.<technique>.* of the OIT technique: its accumulation targets, `reference`'s
    // fragments per pixel), or null when it has no texture (fog.radiance where the march skips
    // it).
    const gpu::Texture* resourceTexture(const std::string& name) const;
    // Recompiles every shader from disk; failing programs keep their previous version (their
    // messages go to `errors` when given).
    int reloadShaders(std::vector<std::string>* errors = nullptr) {
        shadowMapsValid_ = false; // the shadow passes' programs may have changed
        return programs_.reloadAll(errors);
    }
    // Programs that exist now (tests: a technique switch releases the old technique's).
    std::size_t liveProgramCount() const { return programs_.liveCount(); }

    // Changes that rebuild only what depends on them (the viewer; DESIGN.md "derived
    // structures are rebuilt when what they depend on changed"):
    // Another OIT technique (or other property values): the technique, its transparent and
    // fog-emission programs and its targets (the old technique's programs are deleted; the
    // pass list is rebuilt with the new technique's resources). Meshes, volumes, shadow maps
    // stay. Throws
    // veil::Error (unknown, unavailable, bad property, shader) and then changes nothing.
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
    void addTechniquePrograms();
    void configureFogSegments();
    void updateUniforms();
    void beginFrame();
    void bindFrameState();
    void runPasses(std::size_t first, std::size_t end);
    // targets_.region (and opaqueColor) from region_, before the OIT passes.
    void setOitRegion();
    enum class Subset { Opaque, Transparent, OpaqueCasters, TransparentCasters };
    void drawObjects(const gpu::Program& program, Subset subset) const;

    const scene::Scene& scene_;
    gpu::ContextInfo context_;
    scene::Camera camera_;
    int width_ = 0, height_ = 0;
    std::string oitName_;
    glm::vec3 boundsLo_{0.0f}, boundsHi_{0.0f};

    gpu::ProgramManager programs_;
    gpu::ProgramHandle opaqueProgram_, tonemapProgram_;
    std::vector<gpu::ProgramHandle> transparentPrograms_; // one per OIT geometry pass
    std::vector<gpu::ProgramHandle> fogEmitPrograms_;     // one per OIT geometry pass
    std::unique_ptr<volume::FogPass> fog_;
    Properties aoProperties_;
    std::unique_ptr<AmbientOcclusion> ao_;
    std::vector<GpuMesh> meshes_;
    std::unique_ptr<oit::Technique> oit_;
    // Every program the OIT technique brought (its own, transparent, fog emission, fog
    // segments): released when setOitTechnique() replaces it.
    std::vector<gpu::ProgramHandle> oitPrograms_;
    std::unique_ptr<shadows::Technique> shadows_;
    shadows::ShadowLightSet shadowSet_;
    std::vector<shadows::LightView> shadowViews_;
    shadows::ShadowFrame shadowFrame_;

    gpu::Buffer cameraUbo_{gpu::NoCreate}, lightsUbo_{gpu::NoCreate}, shadowsUbo_{gpu::NoCreate};
    gpu::Texture hdr_{gpu::NoCreate}, depth_{gpu::NoCreate}, ldr_{gpu::NoCreate};
    gpu::Framebuffer opaqueFbo_{gpu::NoCreate};
    oit::OitFrameTargets targets_;
    volume::FogTargets fogTargets_;
    PassList passes_;
    std::size_t firstPerPixelPass_ = 0; // fog, transparent, resolve, tonemap from here on
    std::size_t shadowPassCount_ = 0;   // the shadow technique's passes, first in the list
    // Their banded forms (shadows::ShadowPass::executeRows; null: whole only), by pass index.
    std::vector<std::function<void(int, int)>> shadowRows_;
    bool reuseShadowMaps_ = false;
    bool shadowMapsValid_ = false;  // the maps hold what the shadow passes would draw now
    bool skipShadowPasses_ = false; // this frame's decision (beginFrame())
    std::uint64_t shadowMapRenders_ = 0, shadowMapReuses_ = 0;
    glm::ivec4 region_{0}; // the per-pixel passes' pixels, x0 y0 x1 y1
    Refinement refine_;
    void runPerFramePasses(std::size_t first); // [first, firstPerPixelPass_), then keep opaque
    void refineShadowStep();                   // one band or unbanded pass of the shadow maps
    gpu::Texture opaqueHdr_{gpu::NoCreate}, refinedHdr_{gpu::NoCreate}, refinedLdr_{gpu::NoCreate};
    gpu::StateTracker state_; // every pass's fixed-function state goes through it
    gpu::GpuTimer timer_;
    std::vector<gpu::PassTime> passTimes_;
};

} // namespace veil::frame
