// A scene::MeshData uploaded to GL: one buffer per attribute, an index buffer, a VAO.
#pragma once

#include "gpu/objects.h"
#include "scene/mesh.h"

namespace veil::frame {

class GpuMesh {
public:
    explicit GpuMesh(const scene::MeshData& mesh);
    void draw() const;
    bool billboard() const { return billboard_; }
    std::size_t gpuBytes() const;

private:
    gpu::Buffer positions_, normals_, uvs_, sizes_, indices_;
    gpu::VertexArray vao_;
    GLsizei indexCount_ = 0;
    bool billboard_ = false;
};

} // namespace veil::frame
