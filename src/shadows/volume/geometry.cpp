#include "shadows/volume/geometry.h"

#include "base/error.h"
#include "base/log.h"
#include "shaders/common/bindings.h"
#include "shadows/volume/adjacency.h"

#include <algorithm>
#include <mutex>
#include <set>
#include <string>

namespace veil::shadows {

namespace {

struct SourceVertex { // transform.comp's std430 layout
    glm::vec3 position;
    std::uint32_t object;
};
static_assert(sizeof(SourceVertex) == 16);

struct CasterRange { // draw.glsl's std430 layout
    std::uint32_t firstTriangle, triangles, closed, pad;
};

// Whether `message` is new to this process: the geometry is built again whenever the
// technique is given a scene (twice in one `veil render` of the default scene, once per tile
// of `--shadows all`), and the same mesh's warning is worth one line.
bool firstTime(const std::string& message) {
    static std::mutex mutex;
    static std::set<std::string> seen;
    std::lock_guard lock(mutex);
    return seen.insert(message).second;
}

} // namespace

VolumeGeometry buildVolumeGeometry(const scene::Scene& scene, const std::vector<int>& casters) {
    const std::string where = scene.sourcePath.empty() ? "<scene>" : scene.sourcePath.string();
    std::vector<bool> used(scene.meshes.size(), false), casts(scene.meshes.size(), false);
    for (int c : casters) {
        const scene::Object& object = scene.objects[c];
        casts.at(object.mesh) = true;
        VEIL_CHECK(!scene.meshes[object.mesh].billboard,
                   "{}: shadows 'volume': object '{}' casts shadows with a particle mesh "
                   "('{}'); shadow volumes need triangle meshes (set \"shadows\": false on "
                   "it or use another shadow technique)",
                   where, object.name, scene.meshes[object.mesh].name);
    }
    for (const auto& object : scene.objects)
        if (!scene.materials.at(object.material).isTransparent()) used.at(object.mesh) = true;

    VolumeGeometry g;
    std::vector<Adjacency> adjacency(scene.meshes.size());
    g.meshLo.assign(scene.meshes.size(), glm::vec3(0.0f));
    g.meshHi.assign(scene.meshes.size(), glm::vec3(0.0f));
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        const scene::MeshData& data = scene.meshes[m];
        if (!used[m] || data.billboard) continue;
        adjacency[m] = buildAdjacency(data.positions, data.indices);
        if (casts[m] && !adjacency[m].closed) {
            const std::string message = fmt::format(
                "shadows 'volume': mesh '{}' is not a closed 2-manifold ({}; {} open, {} "
                "non-manifold edges): its triangles are extruded one by one",
                data.name, adjacency[m].reason, adjacency[m].boundaryEdges,
                adjacency[m].nonManifoldEdges);
            if (firstTime(message)) log::warn("{}", message);
        }
        data.bounds(g.meshLo[m], g.meshHi[m]);
    }

    // World vertices: every opaque object with triangles, its mesh's vertices in order.
    std::vector<SourceVertex> source;
    std::vector<std::uint32_t> prepass;
    std::vector<std::uint32_t> worldOffset(scene.objects.size(), 0);
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const scene::Object& o = scene.objects[i];
        if (scene.materials.at(o.material).isTransparent()) continue;
        const Adjacency& adj = adjacency[o.mesh];
        if (adj.indices.empty()) continue;
        const auto base = static_cast<std::uint32_t>(source.size());
        const auto model = static_cast<std::uint32_t>(g.modelObjects.size());
        worldOffset[i] = base;
        g.modelObjects.push_back(static_cast<int>(i));
        for (const glm::vec3& p : scene.meshes[o.mesh].positions)
            source.push_back({p, model});
        for (std::size_t k = 0; k < adj.indices.size(); k += 2) // v0, v1, v2 of each triangle
            prepass.push_back(base + adj.indices[k]);
    }
    std::vector<std::uint32_t> casterIndices;
    std::vector<CasterRange> ranges;
    for (int c : casters) {
        const scene::Object& o = scene.objects[c];
        const Adjacency& adj = adjacency[o.mesh];
        CasterRange r{static_cast<std::uint32_t>(casterIndices.size() / 6),
                      static_cast<std::uint32_t>(adj.indices.size() / 6), adj.closed ? 1u : 0u, 0u};
        for (std::uint32_t k : adj.indices)
            casterIndices.push_back(worldOffset[c] + k);
        ranges.push_back(r);
        g.casterTriangles.push_back(r.triangles);
        g.casterClosed.push_back(adj.closed);
        g.totalCasterTriangles += r.triangles;
    }
    if (source.empty()) source.push_back({glm::vec3(0.0f), 0}); // (no zero-sized buffers)
    if (prepass.empty()) prepass.push_back(0);
    if (casterIndices.empty()) casterIndices.resize(6, 0);
    if (ranges.empty()) ranges.push_back({});

    g.vertexCount = static_cast<int>(source.size());
    g.prepassIndexCount = static_cast<GLsizei>(g.modelObjects.empty() ? 0 : prepass.size());
    g.source = gpu::Buffer();
    g.source.setStorage(std::span<const SourceVertex>(source), 0);
    g.models = gpu::Buffer();
    g.models.setStorage(std::max<std::size_t>(g.modelObjects.size(), 1) * sizeof(glm::mat4),
                        nullptr);
    g.world = gpu::Buffer();
    g.world.setStorage(source.size() * sizeof(glm::vec4), nullptr, 0);
    g.prepassIndices = gpu::Buffer();
    g.prepassIndices.setStorage(std::span<const std::uint32_t>(prepass), 0);
    g.adjacency = gpu::Buffer();
    g.adjacency.setStorage(std::span<const std::uint32_t>(casterIndices), 0);
    g.ranges = gpu::Buffer();
    g.ranges.setStorage(std::span<const CasterRange>(ranges), 0);
    g.prepassVao = gpu::VertexArray();
    g.prepassVao.attribute(VEIL_ATTR_POSITION, 0, g.world, 4, sizeof(glm::vec4))
        .indexBuffer(g.prepassIndices);
    return g;
}

void updateVolumeGeometry(const scene::Scene& scene, VolumeGeometry& g,
                          const gpu::Program& transform) {
    if (g.modelObjects.empty()) return;
    std::vector<glm::mat4> models;
    models.reserve(g.modelObjects.size());
    for (int o : g.modelObjects)
        models.push_back(scene.objects[o].transform);
    g.models.setSubData(0, models.size() * sizeof(glm::mat4), models.data());
    g.source.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_SOURCE);
    g.models.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_MODELS);
    g.world.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_WORLD);
    transform.use();
    transform.set("vertexCount", g.vertexCount);
    glDispatchCompute(static_cast<GLuint>((g.vertexCount + 255) / 256), 1, 1);
    glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
}

} // namespace veil::shadows
