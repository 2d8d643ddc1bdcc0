#include "shadows/shadow_map/shadow_map.h"

#include "base/error.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace veil::shadows {

ShadowMap::ShadowMap(int size) : size_(size), depth_(GL_TEXTURE_2D) {
    VEIL_CHECK(size >= 16 && size <= 16384, "shadow map size {} out of range 16..16384", size);
    depth_.storage2D(1, GL_DEPTH_COMPONENT32F, size, size)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE)
        .parameter(GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    framebuffer_.attach(GL_DEPTH_ATTACHMENT, depth_).drawBuffers({GL_NONE});
    framebuffer_.checkComplete("shadow map");
}

bool ShadowMap::fit(const scene::Light& light, const glm::vec3& lo, const glm::vec3& hi) {
    const glm::vec3 center = 0.5f * (lo + hi);
    const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    const glm::vec3 dir = glm::normalize(light.direction);
    const glm::vec3 up = std::abs(dir.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    if (light.type == scene::LightType::Directional) {
        const glm::vec3 eye = center - dir * (2.0f * radius);
        view_ = glm::lookAt(eye, center, up);
        near_ = radius;
        far_ = 3.0f * radius;
        viewProjection_ = glm::ortho(-radius, radius, -radius, radius, near_, far_) * view_;
        return true;
    }
    if (light.type == scene::LightType::Spot) {
        view_ = glm::lookAt(light.position, light.position + dir, up);
        const float distance = glm::length(center - light.position);
        far_ = distance + radius;
        near_ = std::max(far_ * 1e-3f, distance - radius);
        const float fov = glm::radians(std::min(2.0f * light.outerConeDegrees + 2.0f, 170.0f));
        viewProjection_ = glm::perspective(fov, 1.0f, near_, far_) * view_;
        return true;
    }
    return false;
}

glm::mat4 ShadowMap::textureMatrix() const {
    const glm::mat4 bias = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f)) *
                           glm::scale(glm::mat4(1.0f), glm::vec3(0.5f));
    return bias * viewProjection_;
}

void ShadowMap::render(gpu::StateTracker& state, const std::function<void()>& drawCasters) {
    framebuffer_.bind();
    gpu::PipelineState s;
    s.view(size_, size_).depth(GL_LESS, true);
    state.apply(s); // before the clear: it obeys the depth mask
    const float one = 1.0f;
    glClearNamedFramebufferfv(framebuffer_.id(), GL_DEPTH, 0, &one);
    drawCasters();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

} // namespace veil::shadows
