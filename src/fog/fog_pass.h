// The fog pass of the frame: density volumes of the scene on the GPU, the light-space
// transmittance volumes for self-shadowing, and the compute marcher whose per-pixel result the
// frame hands to the OIT technique through fog_emit.frag; for a technique with fogSegments()
// (`reference`) also the piecewise marcher (fog_segments.comp) run after its surfaces.
// The programs' sampler arrays have exactly the scene's grid volumes (VEIL_VOLUME_SLOTS,
// shaders/volume/volume_common.glsl): constant indices, which llvmpipe needs to be fast.
//
// Parameters (scene "render" block): fog_steps (steps per ray through the volumes' bounds,
// default 128), fog_resolution (1, 2 or 4: marching resolution divisor; upsampled with a joint
// bilateral filter keyed on depth, [McGuire16 sec. 5]), fog_jitter (per-pixel random start offset,
// seeded by render.seed), volume_budget_mib / volume_over_budget (coarsen or refuse),
// fog_octaves / fog_octave_extinction / fog_octave_scattering / fog_octave_anisotropy
// (multiple scattering by octaves [Wrenninge13, Hillaire16], docs/volumes.md), fog_ambient.
// Per volume: density_scale (extinction per unit density), albedo, anisotropy g
// (Henyey-Greenstein), emission, emission_grid or temperature_grid (a second texture of the
// density's layout, docs/volumes.md "Emission"). "homogeneous" volumes add global fog of constant
// density.
#pragma once

#include "gpu/objects.h"
#include "gpu/shader.h"
#include "grid/gpu_volume_stats.h"
#include "pass/pass.h"
#include "scene/scene.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace veil::volume {

class GpuVolume;
class ScatteredLightCache;
struct GridConversion;

class FogPass {
public:
    // Loads and uploads the scene's volumes (throws veil::Error for bad files or budgets).
    // `lightVisibility` is the "veil:light_visibility" include of the frame's shadow
    // technique (lightVisibilityInMedium() per sample toward each light).
    FogPass(const scene::Scene& scene, gpu::ProgramManager& programs,
            const gpu::IncludeAliases& lightVisibility);
    ~FogPass();

    bool active() const { return !volumes_.empty() || globalDensity_ > 0.0f; }
    int divisor() const { return divisor_; }
    // Per-volume statistics (GPU bytes, grid bytes, bricks, ...).
    std::vector<GpuVolumeStats> stats() const;
    std::size_t gpuBytes() const;

    // The frame's pass `fog` (scope Pixels, a receiver of the shadow technique): march() over
    // the context's region (a pixel's march is the same as in the whole frame: its jitter
    // hashes its own coordinate), with updateLightVolumesSlab(slabTexels) as its prepare
    // step for the tiled refinement. Reads depth, writes fog.light_transmittance and
    // fog.radiance.
    std::vector<pass::Pass> passes(int slabTexels);
    // fog.radiance (null where perPixelMarchRuns() is false) and fog.light_transmittance (the
    // first volume's) into the frame's resource table.
    void addResources(pass::Resources& resources) const;

    // Recomputes the light transmittance volumes and marches every pixel. Expects the camera
    // and lights uniform blocks and the shadow map bound (renderer.cpp does this).
    void march(const pass::Context& targets);
    // Step 1 of march() alone: resizes to the targets and recomputes the light transmittance
    // volumes when invalid. The tiled refinement runs it once before its first tile.
    void updateLightVolumes(const pass::Context& targets);
    // Step 1 piecewise (the tiled refinement, one call per UI frame): while the light
    // transmittance volumes are not valid, computes the next `slabTexels` z slices of one
    // volume and returns true; false when they are valid (nothing computed). The slabs
    // together equal updateLightVolumes() bit for bit (a texel depends on its coordinate only).
    bool updateLightVolumesSlab(const pass::Context& targets, int slabTexels);
    // Slabs computed since construction, a whole volume in one piece counting one (tests).
    int lightSlabs() const { return lightSlabs_; }
    // Binds the fog results for fog_emit.frag and sets its uniforms on `program`.
    void bindForEmit(const gpu::Program& program, const pass::Context& targets) const;
    // Draws the full-screen triangle (the emit program must be in use).
    void drawEmit() const;
    // For an OIT technique with fogSegments() (`reference`): the piecewise marcher
    // (fog_segments.comp) with the technique's emit include and defines, added to `programs`
    // for its caller to own (the frame's transparency stage), which then calls marchSegments()
    // after the surfaces of the last geometry pass instead of drawEmit().
    gpu::ProgramHandle addSegmentsProgram(gpu::ProgramManager& programs,
                                          std::vector<std::string> oitDefines,
                                          const std::filesystem::path& oitEmitInclude) const;
    // Whether the frame's transparency takes the fog piecewise (marchSegments()); set by the
    // frame when it assembles its passes. Then the per-pixel march of march() has no reader
    // in the frame: march() only updates the light transmittance volumes, unless a reader of
    // its result (radianceTexture(): --aov fog, --dump) asks to keep it.
    void setPiecewise(bool on) { piecewise_ = on; }
    bool piecewise() const { return piecewise_; }
    void keepPerPixelMarch(bool on) { keepPerPixelMarch_ = on; }
    bool perPixelMarchRuns() const { return !piecewise_ || keepPerPixelMarch_; }
    // Per-pixel marches dispatched since construction (tests).
    int perPixelMarches() const { return perPixelMarches_; }
    // Marches every full-resolution pixel piecewise between the surfaces the technique has
    // stored and emits one contribution per segment; `prepareOit` sets the technique's
    // uniforms on the program (Technique::prepareProgram). After march() in the same frame.
    void marchSegments(const pass::Context& targets, const gpu::Program& program,
                       const std::function<void(const gpu::Program&)>& prepareOit) const;
    // Binds the grid volumes and sets the volume uniforms of shaders/volume/volume_common.glsl
    // on `program` (for other passes that sample the density: shadow techniques).
    void bindVolumes(const gpu::Program& program) const { setVolumeUniforms(program); }
    bool hasGridVolumes() const { return !volumes_.empty(); }
    std::size_t gridVolumeCount() const { return volumes_.size(); }
    // Frame ranges (frame::Renderer::replaceVolumes): grid volume `i` (scene order) takes the
    // data of `converted`, made as this pass converts it (the same options, and the emission
    // channel where the volume has one). Programs stay, and the volume's textures where the new
    // data fits them (GpuVolume::replace()); its light transmittance volume is fitted
    // to the new bounds (reallocated only when its size changes) and recomputed at the next
    // frame. With the scattered-light cache, a volume whose file or grid name changed hands
    // its grid (loadVolume: the PreloadedGridScope's where one is alive) to the cache, which
    // bakes again (ScatteredLightCache::replaceGrid); the same file keeps the cache. Throws
    // veil::Error when the conversion is of another kind.
    void replaceVolume(std::size_t i, const GridConversion& converted);
    // Widens [lo, hi] to the world bounds of every grid volume (the shadow views must hold the
    // media they attenuate and the fog samples they shade; global fog has no bounds).
    void extendBounds(glm::vec3& lo, glm::vec3& hi) const;
    // False when the shadow technique's maps already hold the volumes' absorbance toward
    // every light: the marcher then skips its own self-shadowing volumes.
    void setSelfShadowing(bool on) { selfShadowing_ = on; }
    // The next march() recomputes the light transmittance volumes: the volumes' values
    // (density scale, albedo) or a light changed in the scene, or a benchmark compares with
    // renderers that shadow every frame (veil-bench --relight).
    // Bakes the scattered-light cache (render.fog_scattered_light) when the lights, ambient or
    // volume values changed since its last bake; the frame calls it before its timed passes
    // (frame/stages/fog_stage.h beginFrame), so that the bake is not booked as pass `fog`.
    void prepareScatteredLight();
    // The cache's GPU bake runs at most this long per frame (ms; 0: to its end before the frame):
    // the viewer's progressive bake (ScatteredLightCache::setBudgetMs).
    void setScatteredLightBudgetMs(double ms);
    // Milliseconds of the cache's last bake; -1 without a cache or before its first bake.
    double scatteredLightBakeMs() const;
    const ScatteredLightCache* scatteredLightCache() const { return scattered_.get(); }
    void invalidateLightVolumes() {
        lightValid_ = false;
        slab_ = {};
    }
    // The march's results at 1/divisor() resolution (frame resource "fog.radiance"; not
    // written when perPixelMarchRuns() is false): rgb
    // in-scattered radiance (a: its mean depth) and rgb transmittance (a: opaque view depth).
    const gpu::Texture& radianceTexture() const { return radiance_; }
    const gpu::Texture& transmittanceTexture() const { return transmittance_; }
    // Volume i's light-space transmittance toward the primary light (R16F, 3D; frame resource
    // "fog.light_transmittance"), or null when there is no such volume.
    const gpu::Texture* lightTransmittanceTexture(std::size_t i) const {
        return i < volumes_.size() && volumes_[i].light ? &volumes_[i].light : nullptr;
    }

private:
    void resize(int width, int height);
    bool lightVolumesStale(const pass::Context& targets, glm::vec4& key);
    void setVolumeUniforms(const gpu::Program& program) const;
    void setMarchUniforms(const gpu::Program& program, const pass::Context& targets) const;
    std::string slotsDefine() const;

    const scene::Scene& scene_;
    gpu::ProgramManager& programs_;
    gpu::ProgramHandle marchProgram_, lightProgram_;
    gpu::IncludeAliases lightVisibility_;
    bool piecewise_ = false;
    bool keepPerPixelMarch_ = false;
    int perPixelMarches_ = 0;
    struct Entry {
        const scene::VolumeRef* ref;
        std::unique_ptr<GpuVolume> gpu;
        gpu::Texture light{gpu::NoCreate}; // R16F transmittance toward the primary light
        glm::mat4 lightToWorld{1.0f};
        std::filesystem::path source; // the file and grid the data came from
        std::string sourceGrid;
    };
    std::vector<Entry> volumes_;
    void fitLightVolume(Entry& e);
    std::vector<std::string> marchDefines() const; // slots, and emission where a volume has it
    static int emissionMode(const Entry& e);
    float globalDensity_ = 0.0f;
    glm::vec3 globalAlbedo_{0.0f};
    float globalAnisotropy_ = 0.0f;
    int divisor_ = 1;
    int primaryLight_ = -1;
    int width_ = 0, height_ = 0;
    // Light the transmittance volumes were computed for: they are recomputed only when the
    // primary light moves (derived structures are rebuilt when the light moved).
    glm::vec4 lightKey_{0.0f};
    bool lightValid_ = false;
    struct SlabProgress { // updateLightVolumesSlab(): the next slab while not valid
        bool started = false;
        glm::vec4 key{0.0f};
        std::size_t volume = 0;
        int z = 0;
    } slab_;
    int lightSlabs_ = 0;
    bool selfShadowing_ = true;
    gpu::Texture radiance_{gpu::NoCreate}, transmittance_{gpu::NoCreate};
    bool emissive_ = false;                          // a volume has an emission channel
    std::unique_ptr<ScatteredLightCache> scattered_; // render.fog_scattered_light
    gpu::Texture blackbody_{gpu::NoCreate};          // blackbodyTable() for fog_medium.glsl
    gpu::VertexArray emptyVao_{gpu::NoCreate};
};

} // namespace veil::volume
