// The fog's scattered-light cache on the GPU (render.fog_scattered_light, docs/volumes.md
// "Scattered-light cache"): the path tracer's ScatteredLight (integrators/path_tracer.h) baked on
// the CPU over the grid volumes' bounds, uploaded as two RGBA32F 3D textures (mean radiance,
// P1 flux) that fog_medium.glsl samples per march step. The bake depends on the lights, the
// ambient (sky) radiance and the volumes' values: ensure() bakes again when any of them
// changed since the last bake (a live light edit in the viewer costs one bake).
#pragma once

#include "gpu/objects.h"
#include "gpu/shader.h"
#include "scene/scene.h"

#include <openvdb/openvdb.h>

#include <glm/glm.hpp>

#include <vector>

namespace veil::volume {

class ScatteredLightCache {
public:
    // `grids`: every grid volume's density, in scene order (the path tracer's input).
    ScatteredLightCache(const scene::Scene& scene, std::vector<openvdb::FloatGrid::ConstPtr> grids);

    // Bakes if the scene's lights, ambient or volume values differ from the last bake's.
    void ensure();
    // Binds the textures and sets scatteredLo / scatteredHi on `program`.
    void bind(const gpu::Program& program) const;

    glm::ivec3 dims() const { return dims_; }
    int bakes() const { return bakes_; }
    double lastBakeSeconds() const { return seconds_; }

private:
    std::vector<float> key() const;

    const scene::Scene& scene_;
    std::vector<openvdb::FloatGrid::ConstPtr> grids_;
    glm::dvec3 lo_{0.0}, hi_{0.0};
    glm::ivec3 dims_{0};
    gpu::Texture mean_{gpu::NoCreate}, flux_{gpu::NoCreate};
    std::vector<float> bakedKey_;
    int bakes_ = 0;
    double seconds_ = 0.0;
};

} // namespace veil::volume
