// std140 mirrors of the uniform blocks in shaders/common/camera.glsl and lights.glsl.
#pragma once

#include "shaders/common/bindings.h"

#include <glm/glm.hpp>

namespace veil::frame {

struct CameraBlock {
    glm::mat4 view;
    glm::mat4 projection;
    glm::mat4 viewProjection;
    glm::vec4 cameraPosition;
    glm::vec4 cameraRight;
    glm::vec4 cameraUp;
    glm::vec4 cameraForward; // w = 1 for orthographic
    glm::vec4 viewport;      // width, height, near, far
};
static_assert(sizeof(CameraBlock) == 3 * 64 + 5 * 16);

struct LightEntry {
    glm::vec4 positionType;
    glm::vec4 directionShadow;
    glm::vec4 radiance;
    glm::vec4 cone;
};

struct LightsBlock {
    LightEntry lights[VEIL_MAX_LIGHTS];
    glm::ivec4 lightCount;
    glm::vec4 ambient;
};
static_assert(sizeof(LightsBlock) == VEIL_MAX_LIGHTS * 64 + 16 + 16);

} // namespace veil::frame
