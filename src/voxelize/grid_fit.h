// The grids `veil voxelize` (and the Python module's voxelize()) fit to a scene or a mesh
// file: an orthographic grid along +z world fitted to the bounds with a 3% margin, a
// perspective grid from a scene camera with near/far fitted to the bounds, or, for a bare
// mesh, cubic voxels of (largest extent x 1.06) / res fitted to the mesh bounds on every axis
// (so a flat mesh gets few slices).
#pragma once

#include "scene/scene.h"
#include "voxelize/slice_map.h"
#include "voxelize/triangles.h"

#include <filesystem>
#include <string>

namespace veil::voxelize {

// .obj, .ply, .glb, .gltf (any case): voxelized as a bare mesh.
bool isMeshFile(const std::string& path);

// A scene of one object: the mesh file, with its own materials (veil::Error naming the file).
scene::Scene sceneForMesh(const std::filesystem::path& mesh);

struct GridRequest {
    int res = 256;  // columns per side (a mesh: cells along its largest extent)
    int slices = 0; // slices per column; 0: res (a mesh: as many as its bounds need)
    bool perspective = false;
    std::string camera; // perspective: the scene camera (empty: the first)
};

// The grid for `tris` (of `scene`), as above; `mesh`: the scene came from sceneForMesh.
SliceMap fitGrid(const scene::Scene& scene, const Triangles& tris, const GridRequest& request,
                 bool mesh);

} // namespace veil::voxelize
