// One float or vec3 grid of an OpenVDB file sampled onto a dense axis-aligned point grid:
// what `veil export` writes as VTK ImageData (.vti) and the Python module's export_vti().
//
// Points: the index box (inclusive; default the grid's active bounding box) sampled every
// 1 / resample voxels per axis: resample = 1 gives exactly the voxel values (background where
// inactive), other factors trilinear interpolation in index space
// (openvdb::tools::BoxSampler). Spacing = the grid's voxel size / resample; origin = the world
// position of the box's first index (the grid's own index-to-world transform), so ParaView
// shows the volume where OpenVDB puts it. Transforms that are not axis-aligned scales and
// translations cannot be ImageData and are refused.
#pragma once

#include "io/vtk_export.h" // io::DenseGrid: a plain struct (no link to veil_io)

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace veil::vdb {

struct SampledGrid {
    io::DenseGrid dense;
    std::size_t index = 0; // the grid's index in the file
    std::string name, type;
    std::array<int, 3> boxMin{0, 0, 0}, boxMax{0, 0, 0}; // the index box sampled, inclusive
};

// Most points sampled: 2^28 floats are 1 GiB before VTK's own copy.
constexpr double kMaxSampledPoints = 268435456.0;

// `selector`: grid name or index (empty: the first float or vec3 grid); `box`: empty or
// x0 y0 z0 x1 y1 z1; `resample` > 0. Throws veil::Error naming the file and the grid.
SampledGrid sampleVdbGrid(const std::filesystem::path& input, const std::string& selector,
                          const std::vector<int>& box, double resample);

} // namespace veil::vdb
