// The fog's scattered-light cache on the GPU (render.fog_scattered_light, docs/scattered-light.md):
// the path tracer's ScatteredLight (integrators/path_tracer.h) over the grid volumes' bounds, as
// two RGBA32F 3D textures (mean radiance, P1 flux) that fog_medium.glsl samples per march step.
// Baked by a compute shader (scattered_light_bake.h) or by the CPU path tracer, per
// render.fog_scattered_light_bake (auto: the GPU on hardware, the CPU on software renderers). The
// bake depends on the lights, the ambient (sky) radiance and the volumes' values: ensure() bakes
// again when any of them changed since the last bake. The GPU bake can be progressive
// (setBudgetMs(), the viewer: render.fog_scattered_light_budget_ms): each ensure() then runs it for
// the budget and the frame draws with the paths so far, until every texel has its samples; an edit
// meanwhile starts it again. Otherwise (`veil render`, Python, the CPU bake) ensure() bakes to the
// end. A full bake names itself on the progress line of a long render (base/progress.h), with an
// estimate.
#pragma once

#include "gpu/objects.h"
#include "gpu/shader.h"
#include "scene/scene.h"

#include <openvdb/openvdb.h>

#include <glm/glm.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace veil::volume {

class ScatteredLightBake;

// What the GPU bake needs of the fog pass: its program manager, the defines of its volume
// programs (VEIL_VOLUME_SLOTS, VEIL_VOLUME_EMISSION) and a binder of its density textures
// and volume uniforms. Without a program manager the cache is baked on the CPU.
struct ScatteredLightGpu {
    gpu::ProgramManager* programs = nullptr;
    std::vector<std::string> defines;
    std::function<void(const gpu::Program&)> bindVolumes;
    int coarsened = 0; // the most times a GPU copy of a grid was coarsened (its majorants' margin)
};

// The progressive bake's milliseconds for the next frame (the viewer, veil-bench --light-drag):
// render.fog_scattered_light_budget_ms (`budgetMs`), raised to what the previous frame's passes
// (`passesMs`, the bake not among them) left of render.fog_scattered_light_frame_ms
// (`frameMs`): the bake fills the frame up to that frame time and converges as fast as the
// frame rate allows. 0 stays 0 (the whole bake before the frame).
double progressiveBakeMs(double budgetMs, double frameMs, double passesMs);

class ScatteredLightCache {
public:
    // `grids`: every grid volume's density, in scene order (the path tracer's input).
    ScatteredLightCache(const scene::Scene& scene, std::vector<openvdb::FloatGrid::ConstPtr> grids,
                        ScatteredLightGpu gpu = {});
    ~ScatteredLightCache();

    // Bakes if the scene's lights, ambient or volume values differ from the last bake's, or a
    // grid was replaced (or goes on with a progressive bake in flight). The camera is no part
    // of the bake: frames that only move it keep the cache.
    void ensure();
    // Frame ranges (FogPass::replaceVolume): grid volume `i` (scene order) now has the data of
    // `grid`, its GPU copy coarsened `coarsened` times at most. Another grid than the one the
    // cache holds makes the next ensure() bake again, over the bounds and majorants of the new
    // grids (computed here), exactly as a cache built on them would (the same grid: nothing). A GPU
    // bake keeps its textures: a progressive bake starts from the previous frame's values, each
    // texel replaced by the new frame's as its first paths come in.
    void replaceGrid(std::size_t i, openvdb::FloatGrid::ConstPtr grid, int coarsened);
    // Milliseconds of GPU bake per ensure() (0, the default: the whole bake in one ensure()).
    void setBudgetMs(double ms) { budgetMs_ = ms; }
    double budgetMs() const { return budgetMs_; }
    // A progressive GPU bake that has not all its samples yet.
    bool converging() const;
    // Binds the textures and sets scatteredLo / scatteredHi on `program`.
    void bind(const gpu::Program& program) const;

    glm::ivec3 dims() const { return dims_; }
    glm::dvec3 lo() const { return lo_; } // the grid's world box
    glm::dvec3 hi() const { return hi_; }
    // The GPU bake (tests read its result back), or null where the CPU bakes.
    const ScatteredLightBake* gpuBake() const { return bake_.get(); }
    int bakes() const { return bakes_; }
    // Where the bakes run: true on the GPU (compute), false on the CPU (the path tracer).
    bool bakesOnGpu() const { return bake_ != nullptr; }
    // Wall time of the last complete bake (a progressive one: the sum of its steps).
    double lastBakeSeconds() const { return seconds_; }

private:
    std::vector<float> key() const;
    void layout(); // bounds, texel grid and (GPU bake) majorants of grids_
    void startGpuBake();
    void bakeOnCpu();

    const scene::Scene& scene_;
    std::vector<openvdb::FloatGrid::ConstPtr> grids_;
    glm::dvec3 lo_{0.0}, hi_{0.0};
    glm::ivec3 dims_{0};
    gpu::Texture mean_{gpu::NoCreate}, flux_{gpu::NoCreate};
    std::vector<float> bakedKey_;
    std::unique_ptr<ScatteredLightBake> bake_; // the GPU bake, when chosen
    std::vector<double> gridMax_;              // each grid's largest value
    // The majorant grid (majorant_grid.h): its size and per grid the unscaled majorants.
    glm::ivec3 majorantDims_{0};
    std::vector<std::vector<float>> gridMajorants_;
    int coarsened_ = 0;   // ScatteredLightGpu::coarsened
    int dataVersion_ = 0; // grids replaced with other data (part of the key)
    int bakes_ = 0;
    bool started_ = false;     // a bake began (bakedKey_ is its key)
    double seconds_ = 0.0;     // of the last complete bake
    double bakeSeconds_ = 0.0; // of the bake in flight so far
    double budgetMs_ = 0.0;
};

} // namespace veil::volume
