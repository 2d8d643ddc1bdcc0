// What `veil voxelize` and the Python module's voxelize() run on a scene or a mesh file: its
// triangles flattened and the grid fitted to them (grid_fit.h; no GL yet, so a bad camera or
// an empty scene fails before a context exists), the grid filled on the GPU
// (gpu_voxelizer.h), then on request converted into OpenVDB grids (vdb_convert.h).
#pragma once

#include "gpu/context.h"
#include "scene/scene.h"
#include "voxelize/gpu_voxelizer.h"
#include "voxelize/grid_fit.h"
#include "voxelize/slice_map.h"
#include "voxelize/triangles.h"
#include "voxelize/vdb_convert.h"

#include <functional>
#include <string>

namespace veil::voxelize {

struct Voxelization {
    Triangles triangles;
    SliceMap grid;             // fitted by prepareVoxelization, filled by fillGrid
    std::string path;          // what ran (GpuVoxelizer::path), after fillGrid
    double milliseconds = 0.0; // its GPU time
};

// The scene's triangles and the grid fitted to them (`mesh`: a bare mesh file's grid).
Voxelization prepareVoxelization(const scene::Scene& scene, const GridRequest& request, bool mesh);

// Fills v.grid in the current context of `info`; `progress` gets the fraction done between
// draw batches (when set).
void fillGrid(Voxelization& v, const gpu::ContextInfo& info, const VoxelizeOptions& options,
              const std::function<void(double)>& progress = {});

// toVdb with `source` (the input's name) before its errors: "mesh.obj: ...".
VdbGrids toVdbNamed(const SliceMap& grid, const VdbOptions& options, const std::string& source);

} // namespace veil::voxelize
