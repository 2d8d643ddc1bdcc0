// Grids read ahead of time (src/sequence reads a frame range's grids on worker threads): while
// a PreloadedGrids scope is alive on a thread, loadVolume() on that thread takes a grid of the
// same file and grid name from it instead of reading the file.
#pragma once

#include <openvdb/openvdb.h>

#include <filesystem>
#include <string>
#include <vector>

namespace veil::volume {

struct PreloadedGrid {
    std::filesystem::path path;
    std::string grid;
    openvdb::FloatGrid::Ptr value; // as loadDensityGrid() returns it
};

class PreloadedGridScope {
public:
    explicit PreloadedGridScope(const std::vector<PreloadedGrid>& grids);
    ~PreloadedGridScope();
    PreloadedGridScope(const PreloadedGridScope&) = delete;
    PreloadedGridScope& operator=(const PreloadedGridScope&) = delete;

private:
    const std::vector<PreloadedGrid>* previous_;
};

// The grid of `path` and `grid` in `grids`, or null.
openvdb::FloatGrid::Ptr findPreloadedGridIn(const std::vector<PreloadedGrid>& grids,
                                            const std::filesystem::path& path,
                                            const std::string& grid);

// The grid of the innermost scope on this thread, or null.
openvdb::FloatGrid::Ptr findPreloadedGrid(const std::filesystem::path& path,
                                          const std::string& grid);

} // namespace veil::volume
