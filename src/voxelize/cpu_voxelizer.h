// CPU reference voxelizer in double precision (no GL), the yardstick of the GPU methods.
//   surface: a cell is set iff its closed box overlaps a triangle, decided exactly by the
//            separating axis test of [AkenineMoller01]: 3 box axes, the triangle normal
//            and the 9 edge x axis cross products.
//   solid:   a cell is set iff the number of triangle crossings of its column's centre line
//            below the cell centre is odd (closed meshes), i.e. what XOR slice maps compute
//            (each crossing toggles every slice beyond it). Crossings on a shared edge are
//            counted once through a top-left rule on the column centre.
// Both need an orthographic, axis-aligned grid with uniform slicing (makeOrthoGrid).
#pragma once

#include "voxelize/slice_map.h"
#include "voxelize/triangles.h"

#include <glm/glm.hpp>

namespace veil::voxelize {

// Exact closed-box / triangle overlap (separating axis theorem).
bool triangleBoxOverlap(const glm::dvec3& boxCenter, const glm::dvec3& halfSize,
                        const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

// Fills `grid.words` (cleared first).
void voxelizeSurfaceCpu(const Triangles& tris, SliceMap& grid);
void voxelizeSolidCpu(const Triangles& tris, SliceMap& grid);

} // namespace veil::voxelize
