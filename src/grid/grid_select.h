// Choosing one grid of a .vdb file by name or by index, shared by `veil export`, `veil render
// file.vdb` and `veil info`.
#pragma once

#include <openvdb/openvdb.h>

#include <filesystem>
#include <functional>
#include <string>

namespace veil::vdb {

// "float", "vec3s", ... (OpenVDB's value type name).
std::string gridTypeName(const openvdb::GridBase& grid);

// "0 'density' (float), 1 'v' (vec3s)" for messages.
std::string listGrids(const openvdb::GridPtrVec& grids);

struct SelectedGrid {
    openvdb::GridBase::ConstPtr grid;
    std::size_t index = 0;
};

// `selector` is a grid name (the first grid of that name), else a decimal index into the
// file's grids; empty = the first grid that `accept` takes. The chosen grid must satisfy
// `accept` too: a grid of another type is refused naming the file, the grid, its type and
// `wanted` (e.g. "a float or vec3 grid"). Errors list the file's grids.
SelectedGrid selectGrid(const openvdb::GridPtrVec& grids, const std::filesystem::path& file,
                        const std::string& selector,
                        const std::function<bool(const openvdb::GridBase&)>& accept,
                        const std::string& wanted);

} // namespace veil::vdb
