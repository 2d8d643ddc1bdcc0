// The voxelize pass of a light slice map (pass::LightSliceMapRequest): the transparent casters
// into light-space slice maps along every light view ([Eisemann06 sec. 2]), one map per
// material class, with the bit layout, bit masks and pack pass of this module (pack.comp,
// bits.glsl). Optionally local slicing's range pass first ([Eisemann06 sec. 2.2]: per-column
// near and far of the casters, one MIN-blended pass per view). The frame adds the pass when its
// shadow technique asks for the map (transmittance-slicemap) and puts the resource in its
// table (addResources).
#pragma once

#include "gpu/objects.h"
#include "gpu/shader.h"
#include "pass/pass.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace veil::voxelize {

class LightSliceMap {
public:
    // One light view: the layer of the maps, its world -> view and world -> clip matrices.
    struct View {
        int layer = 0;
        glm::mat4 view{1.0f}, viewProjection{1.0f};
    };
    // Throws veil::Error for a method other than raster or conservative.
    LightSliceMap(gpu::ProgramManager& programs, pass::LightSliceMapRequest request);
    LightSliceMap(const LightSliceMap&) = delete;
    LightSliceMap& operator=(const LightSliceMap&) = delete;

    const pass::LightSliceMapRequest& request() const { return request_; }
    // The words of every view and class for this frame's scene (context: state, scene,
    // drawObjects); the range too with local slicing.
    void render(const pass::Context& frame, const std::vector<View>& views);
    // `name` (the words) and `name`.range into `resources`.
    void addResources(pass::Resources& resources) const;

private:
    gpu::ProgramManager& programs_;
    pass::LightSliceMapRequest request_;
    gpu::ProgramHandle sliceProgram_, rangeProgram_, packProgram_;
    gpu::Texture range_{gpu::NoCreate};
    std::vector<gpu::Texture> targets_;
    gpu::Framebuffer sliceFbo_{gpu::NoCreate}, rangeFbo_{gpu::NoCreate};
    gpu::Buffer words_{gpu::NoCreate};
};

} // namespace veil::voxelize
