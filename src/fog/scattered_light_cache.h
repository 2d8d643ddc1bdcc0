// The fog's scattered-light cache on the GPU (render.fog_scattered_light, docs/volumes.md
// "Scattered-light cache"): the path tracer's ScatteredLight (integrators/path_tracer.h) over
// the grid volumes' bounds, as two RGBA32F 3D textures (mean radiance, P1 flux) that
// fog_medium.glsl samples per march step. Baked by a compute shader (scattered_light_bake.h) or
// by the CPU path tracer, per render.fog_scattered_light_bake (auto: the GPU on hardware, the
// CPU on software renderers). The bake depends on the lights, the ambient (sky) radiance and the
// volumes' values: ensure() bakes again when any of them changed since the last bake (a live
// light edit in the viewer costs one bake). A bake names itself on the progress line of a long
// render (base/progress.h), with an estimate.
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
};

class ScatteredLightCache {
public:
    // `grids`: every grid volume's density, in scene order (the path tracer's input).
    ScatteredLightCache(const scene::Scene& scene, std::vector<openvdb::FloatGrid::ConstPtr> grids,
                        ScatteredLightGpu gpu = {});
    ~ScatteredLightCache();

    // Bakes if the scene's lights, ambient or volume values differ from the last bake's.
    void ensure();
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
    double lastBakeSeconds() const { return seconds_; }

private:
    std::vector<float> key() const;

    const scene::Scene& scene_;
    std::vector<openvdb::FloatGrid::ConstPtr> grids_;
    glm::dvec3 lo_{0.0}, hi_{0.0};
    glm::ivec3 dims_{0};
    gpu::Texture mean_{gpu::NoCreate}, flux_{gpu::NoCreate};
    std::vector<float> bakedKey_;
    std::unique_ptr<ScatteredLightBake> bake_; // the GPU bake, when chosen
    std::vector<double> gridMax_;              // each grid's largest value (the majorant's terms)
    int bakes_ = 0;
    double seconds_ = 0.0;
};

} // namespace veil::volume
