#include "grid/vdb_info.h"

#include "base/error.h"
#include "base/text.h"
#include "grid/grid_conversion.h"
#include "grid/grid_select.h"
#include "grid/vdb_file.h"

#include <fmt/format.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Count.h>

#include <algorithm>

namespace veil::vdb {

namespace {

// Min and max over the active values (vectors: their lengths) into `info`.
template <typename GridT>
void valueRange(const openvdb::GridBase& base, GridInfo& info) {
    const auto& grid = static_cast<const GridT&>(base);
    if (grid.activeVoxelCount() == 0) {
        info.valueRange = "no active values";
        return;
    }
    if constexpr (openvdb::VecTraits<typename GridT::ValueType>::IsVec) {
        double lo = 1e300, hi = -1e300;
        for (auto it = grid.cbeginValueOn(); it; ++it) {
            const double l = it->length();
            lo = std::min(lo, l);
            hi = std::max(hi, l);
        }
        info.min = lo;
        info.max = hi;
        info.valueRange = fmt::format("|value| min {:.6g}, max {:.6g}", lo, hi);
    } else {
        const auto mm = openvdb::tools::minMax(grid.tree());
        info.min = double(mm.min());
        info.max = double(mm.max());
        info.valueRange = fmt::format("min {:.6g}, max {:.6g}", info.min, info.max);
    }
    info.hasRange = true;
}

void valueRangeOf(const openvdb::GridBase& g, GridInfo& info) {
    if (g.isType<openvdb::FloatGrid>()) return valueRange<openvdb::FloatGrid>(g, info);
    if (g.isType<openvdb::DoubleGrid>()) return valueRange<openvdb::DoubleGrid>(g, info);
    if (g.isType<openvdb::Int32Grid>()) return valueRange<openvdb::Int32Grid>(g, info);
    if (g.isType<openvdb::Int64Grid>()) return valueRange<openvdb::Int64Grid>(g, info);
    if (g.isType<openvdb::Vec3SGrid>()) return valueRange<openvdb::Vec3SGrid>(g, info);
    if (g.isType<openvdb::Vec3DGrid>()) return valueRange<openvdb::Vec3DGrid>(g, info);
    info.valueRange = "min/max n/a for " + g.valueType();
}

} // namespace

FileInfo describeVdbFile(const std::filesystem::path& path, const std::string& selector) {
    // OpenVDB would block on a FIFO and read /dev/zero forever.
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    VEIL_CHECK(!std::filesystem::exists(st) || std::filesystem::is_regular_file(st),
               "cannot read '{}': not a regular file", path.string());
    const openvdb::GridPtrVecPtr grids = volume::readVdbFile(path);
    std::vector<std::size_t> which;
    if (selector.empty()) {
        for (std::size_t i = 0; i < grids->size(); ++i)
            which.push_back(i);
    } else {
        which.push_back(
            selectGrid(
                *grids, path, selector, [](const openvdb::GridBase&) { return true; }, "a grid")
                .index);
    }
    FileInfo out;
    out.gridCount = grids->size();
    for (std::size_t i : which) {
        const openvdb::GridBase& g = *(*grids)[i];
        GridInfo info;
        info.index = i;
        info.name = g.getName();
        info.type = g.valueType();
        info.gridClass = openvdb::GridBase::gridClassToString(g.getGridClass());
        info.activeVoxels = g.activeVoxelCount();
        valueRangeOf(g, info);
        const openvdb::CoordBBox box = g.evalActiveVoxelBoundingBox();
        const openvdb::Vec3d vs = g.voxelSize();
        const openvdb::BBoxd world = g.transform().indexToWorld(box);
        for (int a = 0; a < 3; ++a) {
            info.indexMin[a] = box.min()[a];
            info.indexMax[a] = box.max()[a];
            info.voxelSize[a] = vs[a];
            info.worldMin[a] = world.min()[a];
            info.worldMax[a] = world.max()[a];
        }
        info.transform = g.transform().mapType();
        if (g.isType<openvdb::FloatGrid>() && g.activeVoxelCount() > 0) {
            const auto& grid = static_cast<const openvdb::FloatGrid&>(g);
            info.gridBytes = grid.memUsage();
            info.gpuBytes = volume::estimateGpuBytes(grid, {});
        }
        for (auto m = g.beginMeta(); m != g.endMeta(); ++m)
            info.metadata.push_back(
                {m->first, m->second->typeName(), printable(m->second->str(), 200)});
        out.grids.push_back(std::move(info));
    }
    return out;
}

} // namespace veil::vdb
