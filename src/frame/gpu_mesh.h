// A scene::MeshData uploaded to GL: one buffer per attribute, an index buffer, a VAO; and the
// frame's one way of drawing the scene's objects (drawObjects).
#pragma once

#include "gpu/objects.h"
#include "gpu/shader.h"
#include "pass/pass.h"
#include "scene/mesh.h"
#include "scene/scene.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace veil::frame {

class GpuMesh {
public:
    explicit GpuMesh(const scene::MeshData& mesh);
    void draw() const;
    // Binds the attribute and index buffers as SSBOs at VEIL_SSBO_MESH_* (compute readers).
    void bindStorage() const;
    std::uint32_t triangleCount() const { return static_cast<std::uint32_t>(indexCount_ / 3); }
    bool billboard() const { return billboard_; }
    std::size_t gpuBytes() const;

private:
    gpu::Buffer positions_, normals_, uvs_, sizes_, indices_;
    gpu::VertexArray vao_;
    GLsizei indexCount_ = 0;
    bool billboard_ = false;
};

// Draws the objects of `set` of `scene` (meshes[i] is scene.meshes[i] uploaded) with `program`
// in use: frame/mesh.vert's inputs and the material uniforms of shaders/frame/material.glsl
// per object. What every pass gets as pass::Context::drawObjects.
void drawObjects(const scene::Scene& scene, const std::vector<GpuMesh>& meshes,
                 const gpu::Program& program, pass::ObjectSet set);
// The same objects for a compute program (pass::Context::objectTriangles, dispatchObjects).
std::vector<std::uint32_t> objectTriangles(const scene::Scene& scene,
                                           const std::vector<GpuMesh>& meshes, pass::ObjectSet set);
void dispatchObjects(const scene::Scene& scene, const std::vector<GpuMesh>& meshes,
                     const gpu::Program& program, pass::ObjectSet set,
                     const std::function<void(std::uint32_t, std::uint32_t)>& dispatch);

} // namespace veil::frame
