#include "grid/density_grid.h"
#include "grid/grid_preload.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/log.h"
#include "grid/vdb_file.h"

#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <mutex>

namespace veil::volume {

namespace fs = std::filesystem;

namespace {

constexpr double kMaxProceduralVoxels = 33554432.0; // 2^25

void initOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

openvdb::GridPtrVecPtr readAllGrids(const fs::path& path) {
    initOpenVdb();
    return readVdbFile(path);
}

GridSummary summarize(const openvdb::GridBase& grid) {
    GridSummary s;
    s.name = grid.getName();
    s.type = grid.valueType();
    s.gridClass = openvdb::GridBase::gridClassToString(grid.getGridClass());
    s.activeVoxels = grid.activeVoxelCount();
    s.indexBounds = grid.evalActiveVoxelBoundingBox();
    s.voxelSize = grid.voxelSize();
    if (!s.indexBounds.empty()) s.worldBounds = grid.transform().indexToWorld(s.indexBounds);
    return s;
}

// Small deterministic hash noise (value noise with smooth interpolation), independent of any
// library's random distributions.
float hash3(int x, int y, int z, std::uint32_t seed) {
    std::uint32_t h = seed * 0x9E3779B1u ^ static_cast<std::uint32_t>(x) * 0x85EBCA77u ^
                      static_cast<std::uint32_t>(y) * 0xC2B2AE3Du ^
                      static_cast<std::uint32_t>(z) * 0x27D4EB2Fu;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12;
    h *= 0x297A2D39u;
    h ^= h >> 15;
    return static_cast<float>(h & 0xFFFFFFu) / static_cast<float>(0xFFFFFFu);
}

float valueNoise(float x, float y, float z, std::uint32_t seed) {
    const int ix = static_cast<int>(std::floor(x)), iy = static_cast<int>(std::floor(y)),
              iz = static_cast<int>(std::floor(z));
    auto smooth = [](float t) { return t * t * (3.0f - 2.0f * t); };
    const float fx = smooth(x - ix), fy = smooth(y - iy), fz = smooth(z - iz);
    float v = 0.0f;
    for (int c = 0; c < 8; ++c) {
        const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
        const float w = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy) * (dz ? fz : 1 - fz);
        v += w * hash3(ix + dx, iy + dy, iz + dz, seed);
    }
    return v;
}

float fbm(float x, float y, float z, std::uint32_t seed) {
    float sum = 0.0f, amp = 0.5f;
    for (int o = 0; o < 5; ++o) {
        sum += amp * valueNoise(x, y, z, seed + static_cast<std::uint32_t>(o) * 101u);
        x *= 2.03f;
        y *= 2.03f;
        z *= 2.03f;
        amp *= 0.5f;
    }
    return sum; // in [0, ~0.97]
}

} // namespace

std::vector<GridSummary> listGrids(const fs::path& path) {
    std::vector<GridSummary> out;
    const openvdb::GridPtrVecPtr grids = readAllGrids(path); // keep it alive while iterating
    for (const auto& g : *grids)
        out.push_back(summarize(*g));
    return out;
}

std::size_t sanitizeDensity(openvdb::FloatGrid& grid) {
    std::size_t changed = 0;
    for (auto it = grid.beginValueOn(); it; ++it) {
        const float v = *it;
        if (!std::isfinite(v) || v < 0.0f) {
            it.setValue(0.0f);
            ++changed;
        }
    }
    const float bg = grid.background();
    if (!std::isfinite(bg) || bg != 0.0f) {
        // A fog density's background is empty space.
        grid.tree().root().setBackground(0.0f, true);
        ++changed;
    }
    return changed;
}

namespace {

// The largest half float: the GPU stores emission channels as 16-bit floats (fog/gpu_volume.h),
// where a larger value is infinite and the marcher's trilinear samples and products NaN.
constexpr float kMaxEmissionValue = 65504.0f;

// Emission values (of `role`, a temperature or emission grid) beyond the range of what the GPU
// stores, or NaN/infinite: refused with the file, grid, value and voxel. Inactive values and
// the background count: the samplers read them beside active voxels.
void checkEmissionValues(const openvdb::FloatGrid& grid, const fs::path& path,
                         const std::string& role) {
    auto check = [&](float v, const openvdb::Coord& at, bool active) {
        VEIL_CHECK(std::isfinite(v) && std::fabs(v) <= kMaxEmissionValue,
                   "grid '{}' of '{}' ({}) holds {} at voxel [{} {} {}]{}: emission values must "
                   "be finite and within +-{} (the GPU stores them as 16-bit floats); rescale "
                   "the grid and raise {}",
                   grid.getName(), path.string(), role, v, at.x(), at.y(), at.z(),
                   active ? "" : " (inactive)", kMaxEmissionValue,
                   role == "temperature_grid" ? "temperature_scale" : "emission");
    };
    check(grid.background(), openvdb::Coord(0), false);
    for (auto it = grid.cbeginValueAll(); it; ++it)
        check(*it, it.getCoord(), it.isValueOn());
}

// A scalar grid of a file; `role` names what it is for in the messages ("density",
// "temperature_grid", ...). With `colour`, a vec3s grid is accepted too: it is returned there
// (null returned).
openvdb::FloatGrid::Ptr loadScalarGrid(const fs::path& path, const std::string& gridName,
                                       const std::string& role,
                                       openvdb::Vec3SGrid::Ptr* colour = nullptr) {
    const openvdb::GridPtrVecPtr grids = readAllGrids(path);
    openvdb::GridBase::Ptr found;
    std::string names;
    for (const auto& g : *grids) {
        names += fmt::format("{}'{}' ({})", names.empty() ? "" : ", ",
                             boundedText(g->getName(), 60), boundedText(g->valueType(), 20));
        if (!found && g->getName() == gridName) found = g;
    }
    VEIL_CHECK(found, "volume '{}' has no grid named '{}'{} (grids: {})", path.string(), gridName,
               role == "density" ? "" : fmt::format(" ({})", role), names.empty() ? "none" : names);
    if (auto vec = colour ? openvdb::gridPtrCast<openvdb::Vec3SGrid>(found) : nullptr) {
        VEIL_CHECK(vec->activeVoxelCount() > 0, "grid '{}' of '{}' is empty (no active voxels)",
                   gridName, path.string());
        *colour = vec;
        return nullptr;
    }
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(found);
    VEIL_CHECK(grid, "grid '{}' of '{}' holds {} values; a {} must be a {} grid", gridName,
               path.string(), found->valueType(), role,
               colour ? "scalar float or vec3s" : "scalar float");
    VEIL_CHECK(grid->activeVoxelCount() > 0, "grid '{}' of '{}' is empty (no active voxels)",
               gridName, path.string());
    if (role != "density") checkEmissionValues(*grid, path, role);
    if (grid->getGridClass() == openvdb::GRID_LEVEL_SET) {
        log::warn("grid '{}' of '{}' is a level set: converted to a fog volume (density 1 "
                  "inside)",
                  gridName, path.string());
        grid = grid->deepCopy();
        openvdb::tools::sdfToFogVolume(*grid);
    }
    if (const std::size_t bad = sanitizeDensity(*grid))
        log::warn("grid '{}' of '{}': {} NaN, infinite or negative values set to 0", gridName,
                  path.string(), bad);
    VEIL_CHECK(grid->activeVoxelCount() > 0, "grid '{}' of '{}' is empty (no active voxels)",
               gridName, path.string());
    return grid;
}

} // namespace

openvdb::FloatGrid::Ptr loadDensityGrid(const fs::path& path, const std::string& gridName) {
    return loadScalarGrid(path, gridName, "density");
}

std::vector<openvdb::FloatGrid::Ptr> loadEmissionChannel(const scene::VolumeRef& ref) {
    const bool temperature = !ref.temperatureGrid.empty();
    if (!temperature && ref.emissionGrid.empty()) return {};
    VEIL_CHECK(ref.procedural.empty(), "volume '{}' is procedural and has no file to read {} from",
               ref.name, temperature ? "temperature_grid" : "emission_grid");
    const std::string& name = temperature ? ref.temperatureGrid : ref.emissionGrid;
    if (openvdb::FloatGrid::Ptr preloaded = findPreloadedGrid(ref.path, name)) return {preloaded};
    if (temperature) return {loadScalarGrid(ref.path, name, "temperature_grid")};
    // Emitted radiance is the grid's value times `emission`, in float on the GPU.
    const float scale = std::max({ref.emission.x, ref.emission.y, ref.emission.z});
    auto checkProduct = [&](float v, const openvdb::Coord& at) {
        VEIL_CHECK(double(std::fabs(v)) * double(scale) <= double(FLT_MAX),
                   "grid '{}' of '{}' (emission_grid) holds {} at voxel [{} {} {}], which times "
                   "emission {} overflows a float",
                   name, ref.path.string(), v, at.x(), at.y(), at.z(), scale);
    };
    openvdb::Vec3SGrid::Ptr colour;
    if (openvdb::FloatGrid::Ptr scalar = loadScalarGrid(ref.path, name, "emission_grid", &colour)) {
        if (double(scale) * kMaxEmissionValue > double(FLT_MAX))
            for (auto it = scalar->cbeginValueAll(); it; ++it)
                checkProduct(*it, it.getCoord());
        return {scalar};
    }
    // A colour: its components as three float grids (negative values 0; values the GPU cannot
    // store refused as for a scalar grid).
    std::vector<openvdb::FloatGrid::Ptr> rgb;
    for (const char* c : {"x", "y", "z"}) {
        rgb.push_back(openvdb::FloatGrid::create(0.0f));
        rgb.back()->setTransform(colour->transform().copy());
        rgb.back()->setName(fmt::format("{}.{}", name, c));
    }
    std::vector<openvdb::FloatGrid::Accessor> acc;
    for (const auto& g : rgb)
        acc.push_back(g->getAccessor());
    for (auto it = colour->cbeginValueOn(); it; ++it) {
        const openvdb::Vec3s v = *it;
        for (int k = 0; k < 3; ++k) {
            VEIL_CHECK(std::isfinite(v[k]) && std::fabs(v[k]) <= kMaxEmissionValue,
                       "grid '{}' of '{}' (emission_grid) holds ({}, {}, {}) at voxel [{} {} "
                       "{}]: emission values must be finite and within +-{} (the GPU stores "
                       "them as 16-bit floats); rescale the grid and raise emission",
                       name, ref.path.string(), v[0], v[1], v[2], it.getCoord().x(),
                       it.getCoord().y(), it.getCoord().z(), kMaxEmissionValue);
            checkProduct(v[k], it.getCoord());
            const float c = v[k] > 0.0f ? v[k] : 0.0f;
            if (it.isVoxelValue()) {
                acc[k].setValue(it.getCoord(), c);
            } else {
                openvdb::CoordBBox box;
                it.getBoundingBox(box);
                rgb[k]->tree().fill(box, c, true);
            }
        }
    }
    return rgb;
}

openvdb::FloatGrid::Ptr makeProceduralGrid(const std::string& kind, const glm::vec3& size,
                                           float voxelSize, std::uint32_t seed) {
    initOpenVdb();
    VEIL_CHECK(voxelSize > 0.0f && std::isfinite(voxelSize),
               "procedural volume: voxel size must be positive");
    VEIL_CHECK(size.x > 0.0f && size.y > 0.0f && size.z > 0.0f &&
                   std::isfinite(size.x + size.y + size.z),
               "procedural volume: size must be positive");
    const glm::vec3 half = 0.5f * size;
    // Every voxel is evaluated (5 octaves of noise for the clouds): 2^25 voxels take seconds,
    // 1e9 took minutes and 4 GB. A finer request is coarsened (voxel size x2) with a warning.
    const glm::dvec3 requested = glm::ceil(glm::dvec3(half) / double(voxelSize));
    double voxels = 8.0 * requested.x * requested.y * requested.z;
    const double requestedVoxels = voxels;
    const float requestedSize = voxelSize;
    while (voxels > kMaxProceduralVoxels) {
        voxelSize *= 2.0f;
        const glm::dvec3 m = glm::ceil(glm::dvec3(half) / double(voxelSize));
        voxels = 8.0 * m.x * m.y * m.z;
    }
    if (voxelSize != requestedSize)
        log::warn("procedural volume '{}' of size ({}, {}, {}) at voxel size {} would have {:.3g} "
                  "voxels, over the limit of {:.3g}: voxel size raised to {}",
                  kind, size.x, size.y, size.z, requestedSize, requestedVoxels,
                  kMaxProceduralVoxels, voxelSize);
    const glm::ivec3 n = glm::ivec3(glm::ceil(half / voxelSize));
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxelSize));
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->setName("density");
    auto acc = grid->getAccessor();
    const float radius = half.x;
    for (int z = -n.z; z < n.z; ++z)
        for (int y = -n.y; y < n.y; ++y)
            for (int x = -n.x; x < n.x; ++x) {
                // Voxel centres at (i + 0.5) h so that the field is symmetric about 0.
                const glm::vec3 p = (glm::vec3(x, y, z) + 0.5f) * voxelSize;
                float d = 0.0f;
                if (kind == "box") {
                    d = 1.0f;
                } else if (kind == "sphere") {
                    d = glm::length(p) <= radius ? 1.0f : 0.0f;
                } else if (kind == "smoke-ball") {
                    const float r = glm::length(p) / radius;
                    const float noise =
                        fbm(p.x / radius * 3.0f, p.y / radius * 3.0f, p.z / radius * 3.0f, seed);
                    d = glm::clamp((1.0f - r) * 2.0f, 0.0f, 1.0f) * (0.4f + 1.2f * noise);
                    d = r < 1.0f ? d : 0.0f;
                } else if (kind == "noise-cloud") {
                    // Thresholded fractal noise inside an ellipsoidal envelope inscribed in
                    // the box: from 70% of the way to the faces the noise is eroded (so the
                    // edge follows the noise), and from 85% the density fades to exactly 0 at
                    // 95%: the silhouette is the noise's, never the box's.
                    const glm::vec3 q = p / glm::max(size.x, glm::max(size.y, size.z)) * 4.0f;
                    const float r = glm::length(p / half);
                    const float erosion = 0.25f * glm::smoothstep(0.7f, 0.95f, r);
                    const float fade = 1.0f - glm::smoothstep(0.85f, 0.95f, r);
                    d = glm::clamp((fbm(q.x, q.y, q.z, seed) - 0.45f - erosion) * 4.0f, 0.0f,
                                   1.0f) *
                        fade;
                } else {
                    throw Error(fmt::format("unknown procedural volume '{}'", kind));
                }
                if (d > 0.0f) acc.setValue(openvdb::Coord(x, y, z), d);
            }
    // Index (i, j, k) has its centre at (i + 0.5) h: shift the transform by half a voxel.
    grid->transform().postTranslate(openvdb::Vec3d(0.5 * voxelSize));
    VEIL_CHECK(grid->activeVoxelCount() > 0, "procedural volume '{}' came out empty", kind);
    return grid;
}

openvdb::FloatGrid::Ptr meshToFogGrid(const scene::MeshData& mesh, const glm::mat4& transform,
                                      float voxelSize, float bandVoxels) {
    initOpenVdb();
    VEIL_CHECK(!mesh.billboard, "mesh '{}': particle clouds have no volume", mesh.name);
    auto xform = openvdb::math::Transform::createLinearTransform(voxelSize);
    std::vector<openvdb::Vec3s> points;
    points.reserve(mesh.positions.size());
    for (const auto& p : mesh.positions) {
        const glm::vec3 w = glm::vec3(transform * glm::vec4(p, 1.0f));
        const openvdb::Vec3d idx = xform->worldToIndex(openvdb::Vec3d(w.x, w.y, w.z));
        points.emplace_back(static_cast<float>(idx.x()), static_cast<float>(idx.y()),
                            static_cast<float>(idx.z()));
    }
    std::vector<openvdb::Vec3I> triangles;
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
        triangles.emplace_back(mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]);
    openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(points,
                                                                                       triangles);
    auto sdf =
        openvdb::tools::meshToVolume<openvdb::FloatGrid>(adapter, *xform, bandVoxels, bandVoxels);
    openvdb::tools::sdfToFogVolume(*sdf);
    sdf->setName("density");
    VEIL_CHECK(sdf->activeVoxelCount() > 0,
               "mesh '{}' gave an empty volume (is it closed? is the voxel size {} too large?)",
               mesh.name, voxelSize);
    return sdf;
}

openvdb::FloatGrid::Ptr loadVolume(const scene::VolumeRef& ref) {
    VEIL_CHECK(ref.procedural != "homogeneous", "volume '{}' is homogeneous fog and has no grid",
               ref.name);
    if (!ref.procedural.empty())
        return makeProceduralGrid(ref.procedural, ref.size, ref.voxelSize, ref.seed);
    if (openvdb::FloatGrid::Ptr preloaded = findPreloadedGrid(ref.path, ref.grid)) return preloaded;
    return loadDensityGrid(ref.path, ref.grid);
}

void saveGrids(const fs::path& path, const openvdb::GridPtrVec& grids) {
    initOpenVdb();
    writeFileAtomically(path, [&](const fs::path& tmp) {
        try {
            const std::lock_guard registries(openVdbIoMutex());
            openvdb::io::File file(tmp.string());
            file.write(grids);
            file.close();
        } catch (const openvdb::Exception& e) {
            throw Error(fmt::format("cannot write '{}': {}", path.string(), e.what()));
        }
    });
}

} // namespace veil::volume
