// GPU slice-map voxelizers ([Eisemann06 sec. 2] slice maps; solid by XOR; [Schwarz10] for
// the compute method).
//
// Methods (parseMethod names):
//   raster        one slice per covered pixel centre ([Eisemann06] as published): thin surfaces,
//   holes
//                 where triangles are steep or thinner than a pixel
//   conservative  GL_NV_conservative_raster where present, else a geometry-shader dilation
//                 to the half-pixel-enlarged bounding rectangle with a per-fragment
//                 pixel/triangle separating-axis test; every fragment sets all slices of the
//                 triangle's depth range over the pixel square (no holes in depth)
//   three-axis    each triangle rasterized along its dominant normal axis into one of three
//                 views of the same uniform orthographic grid, merged by a compute pass
//   compute       compute shader, one thread per triangle, exact triangle/box overlap
//                 (plane + 2D edge tests), atomicOr into the SSBO
// Options: solid (XOR of crossings at column centres; raster only: a conservative fragment
// in a column its triangle does not cross would break the parity),
// local ([Eisemann06 sec. 2.2] per-column near/far from a min/max range pass; raster,
// conservative). Grids with more than 1024 slices take ceil(slices / 1024) geometry passes. Result:
// the slice map's words in an SSBO (binding VEIL_SSBO_VOX_WORDS, queried by
// shaders/voxelize/slice_map.glsl) and, on download(), in SliceMap::words.
#pragma once

#include "gpu/context.h"
#include "gpu/objects.h"
#include "gpu/shader.h"
#include "voxelize/slice_map.h"
#include "voxelize/triangles.h"

#include <functional>
#include <memory>
#include <string>

namespace veil::voxelize {

enum class Method { Raster, Conservative, ThreeAxis, Compute };
Method parseMethod(const std::string& name); // throws veil::Error listing the valid names
std::string methodName(Method method);

struct VoxelizeOptions {
    Method method = Method::Conservative;
    bool solid = false;
    bool local = false;
};

class GpuVoxelizer {
public:
    explicit GpuVoxelizer(const gpu::ContextInfo& info);
    ~GpuVoxelizer();
    GpuVoxelizer(const GpuVoxelizer&) = delete;
    GpuVoxelizer& operator=(const GpuVoxelizer&) = delete;

    void upload(const Triangles& tris);
    // Voxelizes into `grid` (its size and camera; words and local ranges are overwritten and
    // downloaded). Throws veil::Error for unsupported combinations.
    void voxelize(SliceMap& grid, const VoxelizeOptions& options);

    // What ran, e.g. "conservative: geometry-shader dilation (no GL_NV_conservative_raster)".
    const std::string& path() const { return path_; }
    double milliseconds() const { return milliseconds_; } // GPU time of the last voxelize()
    // Binds the words (and range) SSBOs and sets slice_map.glsl's uniforms on `program`.
    void bindSliceMap(const gpu::Program& program, const SliceMap& grid) const;
    // Called with the fraction done between draw batches (only when set).
    std::function<void(double)> progress;
    // Triangles per draw batch (progress granularity).
    std::size_t batchTriangles = 1u << 20;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::string path_;
    double milliseconds_ = 0.0;
};

} // namespace veil::voxelize
