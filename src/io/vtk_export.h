// VTK export for ParaView: dense scalar grids as .vti (vtkXMLImageDataWriter), written to a
// temporary file renamed into place.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace veil::io {

struct DenseGrid {
    std::array<int, 3> dims{0, 0, 0};
    std::array<double, 3> origin{0, 0, 0};  // world position of point (0, 0, 0)
    std::array<double, 3> spacing{1, 1, 1}; // world distance between points per axis
    std::vector<float> values;              // x fastest, then y, then z; `components` per point
    std::string name = "density";
    int components = 1; // 1 (scalars) or 3 (vectors)
    // Further point-data arrays of the same dims, one scalar per point (e.g. a mask).
    std::vector<std::pair<std::string, std::vector<float>>> moreScalars;
    // Where the data came from, written as the image's field data: one vtkStringArray of one
    // value per entry (ParaView: Information panel, Data Arrays).
    std::vector<std::pair<std::string, std::string>> fieldData;
};

void writeVti(const std::filesystem::path& path, const DenseGrid& grid);
// Reads a .vti written by writeVti back (the first point-data array, 1 or 3 components, as
// `values`; further 1-component arrays as moreScalars; string field data); throws
// veil::Error.
DenseGrid readVti(const std::filesystem::path& path);

} // namespace veil::io
