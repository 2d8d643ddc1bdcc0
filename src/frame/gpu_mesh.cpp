#include "frame/gpu_mesh.h"

#include "base/error.h"
#include "shaders/common/bindings.h"

namespace veil::frame {

GpuMesh::GpuMesh(const scene::MeshData& mesh) : billboard_(mesh.billboard) {
    const std::size_t n = mesh.positions.size();
    VEIL_CHECK(n > 0 && !mesh.indices.empty(), "mesh '{}' has no triangles", mesh.name);
    VEIL_CHECK(mesh.normals.size() == n && mesh.uvs.size() == n,
               "mesh '{}': attribute counts differ", mesh.name);
    positions_.setStorage(std::span<const glm::vec3>(mesh.positions), 0);
    normals_.setStorage(std::span<const glm::vec3>(mesh.normals), 0);
    uvs_.setStorage(std::span<const glm::vec2>(mesh.uvs), 0);
    std::vector<float> sizes = mesh.billboardSize;
    sizes.resize(n, 0.0f);
    sizes_.setStorage(std::span<const float>(sizes), 0);
    indices_.setStorage(std::span<const std::uint32_t>(mesh.indices), 0);
    vao_.attribute(VEIL_ATTR_POSITION, 0, positions_, 3, sizeof(glm::vec3))
        .attribute(VEIL_ATTR_NORMAL, 1, normals_, 3, sizeof(glm::vec3))
        .attribute(VEIL_ATTR_UV, 2, uvs_, 2, sizeof(glm::vec2))
        .attribute(VEIL_ATTR_SIZE, 3, sizes_, 1, sizeof(float))
        .indexBuffer(indices_);
    indexCount_ = static_cast<GLsizei>(mesh.indices.size());
}

void GpuMesh::draw() const {
    vao_.bind();
    glDrawElements(GL_TRIANGLES, indexCount_, GL_UNSIGNED_INT, nullptr);
}

std::size_t GpuMesh::gpuBytes() const {
    return positions_.size() + normals_.size() + uvs_.size() + sizes_.size() + indices_.size();
}

} // namespace veil::frame
