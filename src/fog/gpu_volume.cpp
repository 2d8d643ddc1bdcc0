// Uploading a converted grid (gpu_volume.h; the conversion is grid_conversion.cpp).
#include "fog/gpu_volume.h"

#include "base/error.h"
#include "base/log.h"

#include <algorithm>
#include <string>
#include <vector>

namespace veil::volume {

gpu::Texture makeFilteredTexture3D(const glm::ivec3& size, GLenum internalFormat, GLenum format,
                                   const float* texels, GLenum wrap) {
    gpu::Texture t(GL_TEXTURE_3D);
    t.storage3D(1, internalFormat, size.x, size.y, size.z)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_WRAP_S, GLint(wrap))
        .parameter(GL_TEXTURE_WRAP_T, GLint(wrap))
        .parameter(GL_TEXTURE_WRAP_R, GLint(wrap));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(t.id(), 0, 0, 0, 0, size.x, size.y, size.z, format, GL_FLOAT, texels);
    return t;
}

namespace {

// R16F (or, with 4 components, RGBA16F) density texture with clamped edges.
gpu::Texture makeDensityTexture(const glm::ivec3& size, const std::vector<float>& values,
                                int components = 1) {
    return makeFilteredTexture3D(size, components == 4 ? GL_RGBA16F : GL_R16F,
                                 components == 4 ? GL_RGBA : GL_RED, values.data());
}

} // namespace

GpuVolume::GpuVolume(openvdb::FloatGrid::ConstPtr grid, const glm::mat4& objectToWorld,
                     const GpuVolumeOptions& options) {
    VEIL_CHECK(grid && grid->activeVoxelCount() > 0, "empty density grid");
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    upload(convertGrid(*grid, options, max3D), objectToWorld);
}

GpuVolume::GpuVolume(const GridConversion& converted, const glm::mat4& objectToWorld) {
    upload(converted, objectToWorld);
}

void GpuVolume::upload(const GridConversion& c, const glm::mat4& objectToWorld) {
    VEIL_CHECK(!c.values.empty(), "density grid conversion holds no data");
    if (c.stats.coarsened > 0)
        log::warn("grid '{}': {}; coarsened to voxel size x{} ({:.1f} MiB)", c.name,
                  c.coarsenedBecause, 1 << c.stats.coarsened, c.stats.gpuBytes / 1048576.0);
    stats_ = c.stats;
    indexToWorld_ = objectToWorld * c.indexToWorld;
    worldToIndex_ = glm::inverse(indexToWorld_);
    voxelSize_ = std::max({glm::length(glm::vec3(indexToWorld_[0])),
                           glm::length(glm::vec3(indexToWorld_[1])),
                           glm::length(glm::vec3(indexToWorld_[2]))});
    indexMin_ = c.indexMin;
    indexMax_ = c.indexMax;
    leafOrigin_ = c.leafOrigin;
    bricksPerAxis_ = c.bricksPerAxis;
    data_ = makeDensityTexture(c.dataSize, c.values);
    if (!c.channel.empty()) {
        channel_ = makeDensityTexture(c.dataSize, c.channel, c.channelComponents);
        channelComponents_ = c.channelComponents;
    }
    if (!c.neighbourhood.mean.empty()) {
        // GL's default border colour is 0: cells outside the array read 0.
        neighbourhood_ = makeFilteredTexture3D(c.neighbourhood.size, GL_R32F, GL_RED,
                                               c.neighbourhood.mean.data(), GL_CLAMP_TO_BORDER);
        neighbourhoodOrigin_ = c.neighbourhood.origin;
    }
    if (c.stats.dense) return;
    indirection_ = gpu::Texture(GL_TEXTURE_3D);
    indirection_.storage3D(1, GL_R32UI, c.tableSize.x, c.tableSize.y, c.tableSize.z)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureSubImage3D(indirection_.id(), 0, 0, 0, 0, c.tableSize.x, c.tableSize.y, c.tableSize.z,
                        GL_RED_INTEGER, GL_UNSIGNED_INT, c.table.data());
}

void GpuVolume::worldBounds(glm::vec3& lo, glm::vec3& hi) const {
    lo = glm::vec3(1e30f);
    hi = glm::vec3(-1e30f);
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 p((c & 1) ? indexMax_.x : indexMin_.x, (c & 2) ? indexMax_.y : indexMin_.y,
                          (c & 4) ? indexMax_.z : indexMin_.z);
        const glm::vec3 w = glm::vec3(indexToWorld_ * glm::vec4(p, 1.0f));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
}

} // namespace veil::volume
