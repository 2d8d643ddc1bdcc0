// Williams shadow map for opaque casters from one directional or spot light, filtered with
// PCF in the receiving shaders (shaders/common/lights.glsl).
//
// Parameters (scene "render" block): shadow_map_size (texels per side, default 2048),
// shadow_bias (world-space depth bias, slope-scaled in the shader, default 0.01),
// pcf_radius (taps (2r+1)^2, default 1).
#pragma once

#include "gpu/objects.h"
#include "gpu/pipeline_state.h"
#include "scene/scene.h"

#include <functional>

namespace veil::shadows {

class ShadowMap {
public:
    explicit ShadowMap(int size);

    // Fits the light's projection to the world-space bounds of the casters and receivers.
    // Directional: orthographic along the light direction; spot: perspective with the outer
    // cone as half field of view. Point lights are not supported (returns false).
    bool fit(const scene::Light& light, const glm::vec3& boundsLo, const glm::vec3& boundsHi);

    // Clears the map and calls drawCasters() with depth state bound; drawCasters draws with
    // a program that transforms by viewProjection().
    // GLSL file (relative to shaders/) defining lightVisibility() and
    // lightVisibilityInMedium(); included by receivers as "veil:light_visibility".
    static std::filesystem::path visibilityInclude() {
        return "shadows/shadow_map/visibility.glsl";
    }
    // Draws the casters into the map under the pass's declared state (applied through `state`).
    void render(gpu::StateTracker& state, const std::function<void()>& drawCasters);

    const glm::mat4& viewProjection() const { return viewProjection_; }
    const glm::mat4& view() const { return view_; }
    // Range of the linear depth (distance along the light axis) the map stores as 0..1.
    float nearPlane() const { return near_; }
    float farPlane() const { return far_; }
    // world -> [0,1]^3 texture coordinates and depth
    glm::mat4 textureMatrix() const;
    const gpu::Texture& texture() const { return depth_; }
    int size() const { return size_; }

private:
    int size_;
    gpu::Texture depth_;
    gpu::Framebuffer framebuffer_;
    glm::mat4 viewProjection_{1.0f};
    glm::mat4 view_{1.0f};
    float near_ = 0.0f, far_ = 1.0f;
};

} // namespace veil::shadows
