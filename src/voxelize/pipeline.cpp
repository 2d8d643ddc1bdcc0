// The voxelization pipeline (pipeline.h).
#include "voxelize/pipeline.h"

#include "base/error.h"

#include <fmt/format.h>

namespace veil::voxelize {

Voxelization prepareVoxelization(const scene::Scene& scene, const GridRequest& request, bool mesh) {
    Voxelization v;
    v.triangles = flattenScene(scene);
    v.grid = fitGrid(scene, v.triangles, request, mesh);
    return v;
}

void fillGrid(Voxelization& v, const gpu::ContextInfo& info, const VoxelizeOptions& options,
              const std::function<void(double)>& progress) {
    GpuVoxelizer vox(info);
    if (progress) vox.progress = progress;
    vox.upload(v.triangles);
    vox.voxelize(v.grid, options);
    v.path = vox.path();
    v.milliseconds = vox.milliseconds();
}

VdbGrids toVdbNamed(const SliceMap& grid, const VdbOptions& options, const std::string& source) {
    try {
        return toVdb(grid, options);
    } catch (const Error& e) {
        throw Error(fmt::format("{}: {}", source, e.what()));
    }
}

} // namespace veil::voxelize
