// Density fields as openvdb::FloatGrid: loaded from .vdb by name, built procedurally or from
// a mesh, sanitized, saved. The grid keeps its own index-to-world transform; a scene entry's
// transform is applied on top of it when rendering.
#pragma once

#include "scene/mesh.h"
#include "scene/scene.h"

#include <openvdb/openvdb.h>

#include <filesystem>
#include <string>
#include <vector>

namespace veil::volume {

struct GridSummary {
    std::string name;
    std::string type;      // "float", "vec3s", ...
    std::string gridClass; // "fog volume", "level set", ...
    openvdb::Index64 activeVoxels = 0;
    openvdb::CoordBBox indexBounds;
    openvdb::Vec3d voxelSize;
    openvdb::BBoxd worldBounds;
};

// Every grid of a .vdb file. Throws veil::Error for missing, truncated or corrupt files.
std::vector<GridSummary> listGrids(const std::filesystem::path& path);

// The first grid named `gridName` (files may hold several of one name), as a fog density.
// Errors name the file and list its grids when the name is missing; vector and other
// non-float grids are refused; a level set is converted to a fog volume with a warning; an
// empty grid is refused. NaN/Inf values are replaced by 0 with a warning.
openvdb::FloatGrid::Ptr loadDensityGrid(const std::filesystem::path& path,
                                        const std::string& gridName);

// The emission channel a volume entry names, loaded as loadDensityGrid() loads a density (the
// same checks; the messages name the key): none (empty), one grid (a temperature_grid or a
// scalar emission_grid) or three (a vec3s emission_grid's x, y, z: linear RGB). Unlike a
// density, a value that is NaN, infinite or beyond +-65504 (what the GPU's 16-bit float
// channel holds), or whose product with `emission` overflows a float, is refused (veil::Error
// naming the file, grid and voxel), not set to 0.
std::vector<openvdb::FloatGrid::Ptr> loadEmissionChannel(const scene::VolumeRef& ref);

// Procedural density (VolumeRef::procedural other than "homogeneous"): "box", "sphere",
// "smoke-ball", "noise-cloud"; centred at the origin with `voxelSize`, deterministic per seed.
// More than 2^25 voxels are not evaluated: the voxel size is doubled until the grid has at most
// that many, with a warning giving the requested count and the limit.
openvdb::FloatGrid::Ptr makeProceduralGrid(const std::string& kind, const glm::vec3& size,
                                           float voxelSize, std::uint32_t seed);

// A closed mesh turned into a fog volume: openvdb::tools::meshToVolume (signed distance) then
// sdfToFogVolume (density 1 inside, a linear ramp over `bandVoxels` inside the surface).
openvdb::FloatGrid::Ptr meshToFogGrid(const scene::MeshData& mesh, const glm::mat4& transform,
                                      float voxelSize, float bandVoxels = 3.0f);

// Loads what a scene's volume entry names (file or procedural; not "homogeneous").
openvdb::FloatGrid::Ptr loadVolume(const scene::VolumeRef& ref);

// Replaces NaN/Inf by 0 and clamps negative densities to 0; returns how many values changed.
std::size_t sanitizeDensity(openvdb::FloatGrid& grid);

// Writes grids to a .vdb (temporary file + rename).
void saveGrids(const std::filesystem::path& path, const openvdb::GridPtrVec& grids);

} // namespace veil::volume
