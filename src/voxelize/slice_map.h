// Slice maps [Eisemann06 sec. 2]: a grid camera's image of w x h columns; each column holds
// `slices` bits, one per cell along the view axis, packed 32 slices per uint32 word.
//
// Parameters
//   width, height  columns (the grid camera's image size)
//   slices         cells per column ([Eisemann06]: "slices"); any count, words per column =
//   ceil(s/32) viewProj       world -> clip of the grid camera (OpenGL, NDC depth -1..1)
//   perspective    false: slice coordinate = window depth (linear for ortho);
//                  true : slice coordinate = linear eye depth (near..far -> 0..1), so slices
//                  have equal thickness along each ray ([Eisemann06 sec. 2] "division scheme")
//   nearDepth/farDepth  local slicing [Eisemann06 sec. 2.2]: per column range of the slice
//   coordinate
//                  that the column's slices subdivide; empty = uniform [0,1]
//   words          column-contiguous: words[(y * width + x) * wordsPerColumn() + w], bit b of
//                  word w = slice 32 w + b. The GPU keeps the same layout in an SSBO
//                  (shaders/voxelize/slice_map.glsl holds the same queries).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace veil::voxelize {

struct SliceMap {
    int width = 0, height = 0, slices = 0;
    glm::dmat4 viewProj{1.0};
    bool perspective = false;
    double nearPlane = 0.0, farPlane = 1.0; // perspective: eye-space near/far of viewProj
    std::vector<float> nearDepth, farDepth; // local slicing; empty = uniform
    std::vector<std::uint32_t> words;

    int wordsPerColumn() const { return (slices + 31) / 32; }
    std::size_t columnIndex(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }
    bool local() const { return !nearDepth.empty(); }
    void allocate(); // zeroes words for the current size

    // --- cell access ---------------------------------------------------------------------
    bool get(int x, int y, int s) const;
    void set(int x, int y, int s);
    std::uint64_t countSet() const;

    // --- coordinates -----------------------------------------------------------------------
    // Slice coordinate in [0,1] of a window depth (0..1) and back (see `perspective`).
    double depthToSliceCoord(double windowDepth) const;
    double sliceCoordToDepth(double t) const;
    // Column range of the slice coordinate (local slicing or [0,1]).
    void columnRange(int x, int y, double& t0, double& t1) const;
    // World point -> (column x, column y, slice); false outside the grid.
    bool locate(const glm::dvec3& world, int& x, int& y, int& s) const;
    // World position of the centre of cell (x, y, s).
    glm::dvec3 cellCenter(int x, int y, int s) const;

    // --- queries shared with GLSL (shaders/voxelize/slice_map.glsl) -----------------------
    bool occupied(const glm::dvec3& world) const;
    // Number of set slices in [s0, s1] of a column (popcount across words).
    int countOccupied(int x, int y, int s0, int s1) const;
    int firstOccupied(int x, int y) const; // -1 if the column is empty
    int lastOccupied(int x, int y) const;  // -1 if the column is empty
    // World-space length along the column's view axis covered by set slices.
    double thickness(int x, int y) const;
};

// An orthographic grid camera whose columns run along +z world and whose image axes are
// world x and y: cell (x, y, s) is the box lo + [x, y, s] * voxel ... + voxel.
// `slices` cells along z; width/height along x/y.
SliceMap makeOrthoGrid(const glm::dvec3& lo, const glm::dvec3& hi, int width, int height,
                       int slices);
// A cube-voxel orthographic grid of `res`^3 cells enclosing [lo, hi] with a margin of 3% of
// the largest extent on every side (so faces of boxes do not fall on cell planes).
SliceMap makeFittedCubeGrid(const glm::dvec3& lo, const glm::dvec3& hi, int res);
// The three axis-aligned views of an orthographic grid used by dominant-axis voxelization:
// axis 0 looks along x (columns y,z), 1 along y (columns z,x), 2 along z (columns x,y) =
// the grid itself. Returns an empty-word slice map for that axis.
SliceMap axisView(const SliceMap& grid, int axis);
// Perspective grid camera: eye, target, up, full vertical fov, aspect = width/height.
SliceMap makePerspectiveGrid(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up,
                             double fovYDegrees, double nearPlane, double farPlane, int width,
                             int height, int slices);

// World-space corners of an orthographic grid (inverse of viewProj at NDC +-1).
void gridBounds(const SliceMap& map, glm::dvec3& lo, glm::dvec3& hi);

} // namespace veil::voxelize
