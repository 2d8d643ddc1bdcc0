// What a .vdb file holds, grid by grid, as `veil info file.vdb` prints it (like `vdb_print
// -l`) and the Python module's vdb_info() returns it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace veil::vdb {

struct GridInfo {
    std::size_t index = 0;
    std::string name, type, gridClass; // type: OpenVDB's value type name ("float", "vec3s")
    std::uint64_t activeVoxels = 0;
    // Over the active values (vectors: their lengths): "min 0, max 5.71", "no active values",
    // or "min/max n/a for TYPE"; `min`/`max` hold the numbers when `hasRange`.
    std::string valueRange;
    bool hasRange = false;
    double min = 0.0, max = 0.0;
    std::array<int, 3> indexMin{0, 0, 0}, indexMax{0, 0, 0}; // active bounding box, inclusive
    std::array<double, 3> voxelSize{0, 0, 0}, worldMin{0, 0, 0}, worldMax{0, 0, 0};
    std::string transform; // the map type, e.g. "UniformScaleTranslateMap"
    // Float grids with active voxels: the tree's memory and what `veil render` would upload
    // (brick atlas or dense texture, src/fog/gpu_volume.h); 0 otherwise.
    std::size_t gridBytes = 0, gpuBytes = 0;
    // Every metadata entry: name, type name, value as text (at most 200 printable bytes).
    struct Meta {
        std::string name, type, value;
    };
    std::vector<Meta> metadata;
};

struct FileInfo {
    std::size_t gridCount = 0;   // grids in the file
    std::vector<GridInfo> grids; // all of them, or the one `selector` chose
};

// Reads the file (volume/readVdbFile: a corrupt file is a veil::Error naming it). `selector`
// (a name or an index, grid/grid_select.h) describes one grid only; empty: every grid.
FileInfo describeVdbFile(const std::filesystem::path& path, const std::string& selector = {});

} // namespace veil::vdb
