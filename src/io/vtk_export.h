// VTK export for ParaView: dense scalar grids as .vti (vtkXMLImageDataWriter), written to a
// temporary file renamed into place. VTK is optional (VEIL_HAVE_VTK, top-level CMakeLists.txt):
// a build without it compiles vtk_export_stub.cpp, whose functions throw one message saying
// how to get .vti support.
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

// Whether this build writes and reads .vti files (it was built with VTK).
bool vtiSupported();
// Nothing in a build with VTK; otherwise throws veil::Error: "'PATH': this veil was built
// without VTK ...", naming how to install it and that veil must be rebuilt. Commands call it
// before any long work whose result goes to PATH.
void requireVti(const std::filesystem::path& path);

void writeVti(const std::filesystem::path& path, const DenseGrid& grid);
// Reads a .vti written by writeVti back (the first point-data array, 1 or 3 components, as
// `values`; further 1-component arrays as moreScalars; string field data); throws
// veil::Error.
DenseGrid readVti(const std::filesystem::path& path);

} // namespace veil::io
