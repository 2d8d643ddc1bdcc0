// Grids read ahead of time (src/sequence reads a frame range's grids on worker threads): while
// a PreloadedGrids scope is alive on a thread, loadVolume() on that thread takes a grid of the
// same file and grid name from it instead of reading the file, and the fog pass takes its GPU
// conversion (grid_conversion.h) when it was made with the options the pass would use.
#pragma once

#include "grid/grid_conversion.h"

#include <openvdb/openvdb.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace veil::volume {

struct PreloadedGrid {
    std::filesystem::path path;
    std::string grid;
    openvdb::FloatGrid::Ptr value; // as loadDensityGrid() returns it
    // Made ahead from `value` with `options` for GL_MAX_3D_TEXTURE_SIZE `max3D`; may be null.
    std::shared_ptr<const GridConversion> converted;
    GpuVolumeOptions options;
    int max3D = 0;
    // Set: `converted` also holds this grid of the same file as its emission channel
    // (addChannel(), as the fog pass converts a volume with a temperature grid); such a
    // conversion is for frame::Renderer::replaceVolumes, never found by findPreconverted().
    std::string channel;
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

// The conversion of the innermost scope on this thread made for `options` and `max3D`, or null.
std::shared_ptr<const GridConversion> findPreconverted(const std::filesystem::path& path,
                                                       const std::string& grid,
                                                       const GpuVolumeOptions& options, int max3D);

} // namespace veil::volume
