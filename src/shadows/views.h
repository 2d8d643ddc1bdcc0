// The views of the shadow-casting lights (docs/architecture.md "One frame: passes and resources").
// Every light with
// `"shadows": true` gets one view (directional: orthographic along its direction, spot:
// perspective with its outer cone) or six (point: the faces of a cube around it, each a
// perspective view of a little over 90 degrees so that filter kernels near a face edge stay
// inside the face). The views of all shadowed lights are the layers of each shadow
// technique's texture arrays, and shaders/shadows/common/views.glsl reads them from one
// uniform block (ShadowsBlock below, binding VEIL_UBO_SHADOWS).
#pragma once

#include "scene/scene.h"
#include "shaders/common/bindings.h"

#include <glm/glm.hpp>

#include <vector>

namespace veil::shadows {

struct LightView {
    int light = 0;                  // scene light index
    int face = 0;                   // cube face of a point light (+x, -x, +y, -y, +z, -z), else 0
    int layer = 0;                  // layer of the technique's texture arrays
    glm::mat4 view{1.0f};           // world -> light view (depth along the axis = -z)
    glm::mat4 viewProjection{1.0f}; // world -> clip
    float nearPlane = 0.0f, farPlane = 1.0f; // range of the stored normalized linear depth
    bool orthographic = false;
    glm::vec3 position{0.0f};  // the light's position (spot, point) or the view's eye
    glm::vec3 direction{0.0f}; // the view's axis (direction light travels for directional)
};

// Which lights cast shadows and how many views each needs. Throws veil::Error (naming `where`,
// the property path of the limit) when more than `maxLights` lights cast shadows, or their
// views exceed VEIL_MAX_SHADOW_VIEWS: a clear error, never a silently unshadowed light.
struct ShadowLightSet {
    std::vector<int> lights;     // scene light indices, in scene order
    std::vector<int> firstView;  // per entry of `lights`
    std::vector<int> viewCounts; // 1 or 6
    int viewCount = 0;
};
ShadowLightSet chooseShadowLights(const scene::Scene& scene, int maxLights,
                                  const std::string& where);

// Fits the views of `set` to the world bounds of casters and receivers [lo, hi].
std::vector<LightView> fitViews(const scene::Scene& scene, const ShadowLightSet& set,
                                const glm::vec3& lo, const glm::vec3& hi);

// std140 mirror of ShadowsBlock in shaders/shadows/common/views.glsl.
struct ShadowViewEntry {
    glm::mat4 worldToTexture; // viewProjection, then [-1,1] -> [0,1]
    glm::mat4 worldToView;
    glm::vec4 depthRange; // near, far, far - near, orthographic
};
struct ShadowsBlock {
    ShadowViewEntry views[VEIL_MAX_SHADOW_VIEWS];
    glm::ivec4 lights[VEIL_MAX_LIGHTS]; // first view or -1, view count, type, 0
    glm::vec4 mapSize;                  // size, 1 / size, view count, unused
    glm::vec4 params[4];                // technique-defined
};
static_assert(sizeof(ShadowsBlock) ==
              VEIL_MAX_SHADOW_VIEWS * 144 + VEIL_MAX_LIGHTS * 16 + 16 + 4 * 16);

// Fills the views and lights of the block (params are the technique's).
void fillShadowsBlock(ShadowsBlock& block, const std::vector<LightView>& views,
                      const ShadowLightSet& set, int mapSize);

} // namespace veil::shadows
