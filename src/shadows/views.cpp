#include "shadows/views.h"

#include "base/error.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace veil::shadows {

ShadowLightSet chooseShadowLights(const scene::Scene& scene, int maxLights,
                                  const std::string& where) {
    ShadowLightSet set;
    const int usable =
        static_cast<int>(std::min<std::size_t>(scene.lights.size(), VEIL_MAX_LIGHTS));
    for (int i = 0; i < usable; ++i) {
        const scene::Light& light = scene.lights[i];
        if (!light.castShadows) continue;
        const int views = light.type == scene::LightType::Point ? 6 : 1;
        set.lights.push_back(i);
        set.firstView.push_back(set.viewCount);
        set.viewCounts.push_back(views);
        set.viewCount += views;
    }
    const int count = static_cast<int>(set.lights.size());
    VEIL_CHECK(count <= maxLights,
               "{}: {} lights cast shadows, more than max_lights = {} (set \"shadows\": false on "
               "some lights or raise max_lights, at most {})",
               where, count, maxLights, VEIL_MAX_LIGHTS);
    VEIL_CHECK(set.viewCount <= VEIL_MAX_SHADOW_VIEWS,
               "{}: the {} shadow-casting lights need {} views (a point light takes 6), more than "
               "the {} supported (at most 4 point lights)",
               where, count, set.viewCount, VEIL_MAX_SHADOW_VIEWS);
    return set;
}

namespace {

glm::vec3 upFor(const glm::vec3& dir) {
    return std::abs(dir.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
}

// Near and far of a perspective view at `eye` along `dir` that holds the bounding sphere.
void sphereRange(const glm::vec3& eye, const glm::vec3& dir, const glm::vec3& center, float radius,
                 float& nearPlane, float& farPlane) {
    const float along = glm::dot(center - eye, dir);
    farPlane = std::max(along + radius, 1e-3f);
    nearPlane = std::max(farPlane * 1e-3f, along - radius);
}

} // namespace

std::vector<LightView> fitViews(const scene::Scene& scene, const ShadowLightSet& set,
                                const glm::vec3& lo, const glm::vec3& hi) {
    const glm::vec3 center = 0.5f * (lo + hi);
    const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    std::vector<LightView> views;
    for (std::size_t k = 0; k < set.lights.size(); ++k) {
        const scene::Light& light = scene.lights[set.lights[k]];
        LightView v;
        v.light = set.lights[k];
        v.layer = set.firstView[k];
        const glm::vec3 dir = glm::normalize(light.direction);
        if (light.type == scene::LightType::Directional) {
            v.direction = dir;
            v.position = center - dir * (2.0f * radius);
            v.view = glm::lookAt(v.position, center, upFor(dir));
            v.nearPlane = radius;
            v.farPlane = 3.0f * radius;
            v.orthographic = true;
            v.viewProjection =
                glm::ortho(-radius, radius, -radius, radius, v.nearPlane, v.farPlane) * v.view;
            views.push_back(v);
        } else if (light.type == scene::LightType::Spot) {
            v.direction = dir;
            v.position = light.position;
            v.view = glm::lookAt(light.position, light.position + dir, upFor(dir));
            sphereRange(light.position, dir, center, radius, v.nearPlane, v.farPlane);
            const float fov = glm::radians(std::min(2.0f * light.outerConeDegrees + 2.0f, 170.0f));
            v.viewProjection = glm::perspective(fov, 1.0f, v.nearPlane, v.farPlane) * v.view;
            views.push_back(v);
        } else {
            // Point: six faces. The far plane reaches the farthest corner of the bounds; the
            // near plane is a fixed fraction of it (casters closer than that are clipped).
            float farthest = 0.0f;
            for (int c = 0; c < 8; ++c) {
                const glm::vec3 corner((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y,
                                       (c & 4) ? hi.z : lo.z);
                farthest = std::max(farthest, glm::length(corner - light.position));
            }
            const float farPlane = std::max(farthest, 1e-2f);
            const float nearPlane = std::max(farPlane * 1e-3f, 1e-3f);
            // 90 degrees plus a margin of a few texels' worth, so PCF near an edge stays inside.
            const float fov = glm::radians(95.0f);
            static const glm::vec3 axes[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                              {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
            for (int f = 0; f < 6; ++f) {
                LightView face = v;
                face.face = f;
                face.layer = set.firstView[k] + f;
                face.direction = axes[f];
                face.position = light.position;
                face.view = glm::lookAt(light.position, light.position + axes[f], upFor(axes[f]));
                face.nearPlane = nearPlane;
                face.farPlane = farPlane;
                face.viewProjection = glm::perspective(fov, 1.0f, nearPlane, farPlane) * face.view;
                views.push_back(face);
            }
        }
    }
    return views;
}

void fillShadowsBlock(ShadowsBlock& block, const std::vector<LightView>& views,
                      const ShadowLightSet& set, int mapSize) {
    for (const LightView& v : views) {
        ShadowViewEntry& e = block.views[v.layer];
        const glm::mat4 toTexture = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f)) *
                                    glm::scale(glm::mat4(1.0f), glm::vec3(0.5f));
        e.worldToTexture = toTexture * v.viewProjection;
        e.worldToView = v.view;
        e.depthRange = glm::vec4(v.nearPlane, v.farPlane, v.farPlane - v.nearPlane,
                                 v.orthographic ? 1.0f : 0.0f);
    }
    for (int i = 0; i < VEIL_MAX_LIGHTS; ++i)
        block.lights[i] = glm::ivec4(-1, 0, 0, 0);
    for (std::size_t k = 0; k < set.lights.size(); ++k)
        block.lights[set.lights[k]] = glm::ivec4(set.firstView[k], set.viewCounts[k], 0, 0);
    block.mapSize = glm::vec4(static_cast<float>(mapSize), 1.0f / static_cast<float>(mapSize),
                              static_cast<float>(set.viewCount), 0.0f);
}

} // namespace veil::shadows
