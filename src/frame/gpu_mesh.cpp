#include "frame/gpu_mesh.h"

#include "base/error.h"
#include "shaders/common/bindings.h"

#include <glm/gtc/matrix_inverse.hpp>

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

void GpuMesh::bindStorage() const {
    positions_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_MESH_POSITIONS);
    normals_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_MESH_NORMALS);
    uvs_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_MESH_UVS);
    sizes_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_MESH_SIZES);
    indices_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_MESH_INDICES);
}

namespace {

// Calls each(object, mesh) for the objects of `set` in drawing order, after setting their
// uniforms on `program` (when given).
template <class F>
void forEachObject(const scene::Scene& scene, const std::vector<GpuMesh>& meshes,
                   const gpu::Program* program, pass::ObjectSet set, F each) {
    using pass::ObjectSet;
    for (const auto& object : scene.objects) {
        const scene::Material& m = scene.materials.at(object.material);
        const bool transparent = m.isTransparent();
        // A binary-coverage material's alpha = 1 interior is opaque [McGuire17 sec. 6].
        const bool binary = m.baseCoverageIsBinary();
        if (set == ObjectSet::Opaque && transparent && !binary) continue;
        if (set == ObjectSet::Transparent && !transparent) continue;
        if (set == ObjectSet::OpaqueCasters && (transparent || !object.castShadows)) continue;
        if (set == ObjectSet::TransparentCasters && (!transparent || !object.castShadows)) continue;
        const GpuMesh& mesh = meshes.at(object.mesh);
        if (program)
            program->set("model", object.transform)
                .set("normalMatrix", glm::inverseTranspose(glm::mat3(object.transform)))
                .set("billboard", mesh.billboard() ? 1 : 0)
                .set("baseColor", m.baseColor)
                .set("roughness", m.roughness)
                .set("metalness", m.metalness)
                .set("emission", m.emission)
                .set("coverage", m.alpha)
                .set("coverageEdge", m.coverageEdge)
                .set("binaryCoverage", binary ? 1 : 0)
                .set("transmission", m.transmission)
                .set("collimation", m.collimation)
                .set("ior", m.ior)
                .set("attenuationColor", m.attenuationColor)
                .set("attenuationDistance", m.attenuationDistance);
        each(mesh);
    }
}

} // namespace

void drawObjects(const scene::Scene& scene, const std::vector<GpuMesh>& meshes,
                 const gpu::Program& program, pass::ObjectSet set) {
    program.use();
    forEachObject(scene, meshes, &program, set, [](const GpuMesh& mesh) { mesh.draw(); });
    glBindVertexArray(0);
}

std::vector<std::uint32_t> objectTriangles(const scene::Scene& scene,
                                           const std::vector<GpuMesh>& meshes,
                                           pass::ObjectSet set) {
    std::vector<std::uint32_t> counts;
    forEachObject(scene, meshes, nullptr, set,
                  [&](const GpuMesh& mesh) { counts.push_back(mesh.triangleCount()); });
    return counts;
}

void dispatchObjects(const scene::Scene& scene, const std::vector<GpuMesh>& meshes,
                     const gpu::Program& program, pass::ObjectSet set,
                     const std::function<void(std::uint32_t, std::uint32_t)>& dispatch) {
    program.use();
    std::uint32_t index = 0;
    forEachObject(scene, meshes, &program, set, [&](const GpuMesh& mesh) {
        mesh.bindStorage();
        dispatch(index++, mesh.triangleCount());
    });
}

} // namespace veil::frame
