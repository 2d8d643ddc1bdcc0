#include "voxelize/vdb_convert.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "grid/vdb_file.h"

#include <openvdb/io/File.h>
#include <openvdb/tools/Filter.h>
#include <openvdb/tools/Morphology.h>

#include <cmath>

namespace veil::voxelize {

bool isLatticeGrid(const SliceMap& m) {
    if (m.perspective || m.local()) return false;
    // Diagonal scale plus translation (column 3) only.
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (c != r && m.viewProj[c][r] != 0.0) return false;
    return m.viewProj[0][3] == 0.0 && m.viewProj[1][3] == 0.0 && m.viewProj[2][3] == 0.0 &&
           m.viewProj[3][3] == 1.0 && m.viewProj[0][0] > 0.0 && m.viewProj[1][1] > 0.0 &&
           m.viewProj[2][2] > 0.0;
}

VdbGrids toVdb(const SliceMap& map, const VdbOptions& options) {
    openvdb::initialize();
    VEIL_CHECK(!map.words.empty(), "slice map has no words to convert");
    VdbGrids g;
    glm::dvec3 lo, hi;
    gridBounds(map, lo, hi);
    g.mask = openvdb::BoolGrid::create(false);
    auto acc = g.mask->getAccessor();
    if (isLatticeGrid(map)) {
        g.dims = {map.width, map.height, map.slices};
        g.voxel = (hi - lo) / glm::dvec3(g.dims);
        g.origin = lo + 0.5 * g.voxel;
        g.note = "orthographic lattice: linear transform (voxel size, origin at cell centre)";
        for (int y = 0; y < map.height; ++y) {
            for (int x = 0; x < map.width; ++x)
                for (int s = map.firstOccupied(x, y); s >= 0 && s <= map.lastOccupied(x, y); ++s)
                    if (map.get(x, y, s)) acc.setValueOn(openvdb::Coord(x, y, s), true);
            if (options.progress) options.progress(double(y + 1) / map.height);
        }
    } else {
        g.resampled = true;
        const glm::dvec3 e = hi - lo;
        double v = options.resampleVoxel;
        if (v <= 0.0)
            v = std::cbrt(e.x * e.y * e.z / (double(map.width) * map.height * map.slices));
        g.voxel = glm::dvec3(v);
        g.dims = glm::max(glm::ivec3(glm::ceil(e / v)), glm::ivec3(1));
        VEIL_CHECK(double(g.dims.x) * g.dims.y * g.dims.z < 4.0e9,
                   "resampled grid {}x{}x{} is too large: pass a larger voxel size", g.dims.x,
                   g.dims.y, g.dims.z);
        g.origin = lo + 0.5 * g.voxel;
        g.note = fmt::format("{}: resampled into a world-aligned grid of voxel size {:.6g} "
                             "(occupancy at voxel centres)",
                             map.perspective ? "perspective" : "local slicing", v);
        for (int z = 0; z < g.dims.z; ++z) {
            for (int y = 0; y < g.dims.y; ++y)
                for (int x = 0; x < g.dims.x; ++x)
                    if (map.occupied(g.origin + glm::dvec3(x, y, z) * v))
                        acc.setValueOn(openvdb::Coord(x, y, z), true);
            if (options.progress) options.progress(double(z + 1) / g.dims.z);
        }
    }
    const openvdb::math::Vec3d scale(g.voxel.x, g.voxel.y, g.voxel.z),
        shift(g.origin.x, g.origin.y, g.origin.z);
    auto xform = openvdb::math::Transform::Ptr(new openvdb::math::Transform(
        openvdb::math::MapBase::Ptr(new openvdb::math::ScaleTranslateMap(scale, shift))));
    g.mask->setTransform(xform);
    g.mask->setName("mask");
    g.mask->setGridClass(openvdb::GRID_UNKNOWN);

    g.density = openvdb::FloatGrid::create(0.0f);
    g.density->tree().topologyUnion(g.mask->tree());
    for (auto it = g.density->beginValueOn(); it; ++it)
        it.setValue(1.0f);
    if (options.smoothing > 0.0) {
        const int width = std::max(1, static_cast<int>(std::ceil(options.smoothing)));
        // The dilation reaches 2 width voxels around every set voxel (bounded by the grown
        // box), and the Gaussian runs box filters of 2 width + 1 taps along 3 axes, several
        // times: estimate before doing any of it.
        const double grown = double(g.dims.x + 4 * width) * double(g.dims.y + 4 * width) *
                             double(g.dims.z + 4 * width);
        const double around = double(g.mask->activeVoxelCount()) * std::pow(4.0 * width + 1.0, 3.0);
        const double work = std::min(grown, around) * 3.0 * (2.0 * width + 1.0) * 4.0;
        VEIL_CHECK(options.smoothingWorkLimit <= 0.0 || work <= options.smoothingWorkLimit,
                   "smoothing width {} on a {}x{}x{} grid: an estimated {:.3g} voxel updates, "
                   "over the limit of {:.3g} (use a smaller --smooth or a coarser grid, or "
                   "raise --smooth-limit)",
                   width, g.dims.x, g.dims.y, g.dims.z, work, options.smoothingWorkLimit);
        openvdb::tools::dilateActiveValues(g.density->tree(), 2 * width,
                                           openvdb::tools::NN_FACE_EDGE_VERTEX,
                                           openvdb::tools::EXPAND_TILES);
        openvdb::tools::Filter<openvdb::FloatGrid> filter(*g.density);
        filter.gaussian(width, 1);
    }
    g.density->setTransform(xform->copy());
    g.density->setName("density");
    g.density->setGridClass(openvdb::GRID_FOG_VOLUME);
    return g;
}

void writeVdb(const std::filesystem::path& path, const VdbGrids& grids) {
    openvdb::initialize();
    writeFileAtomically(path, [&](const std::filesystem::path& tmp) {
        openvdb::GridPtrVec out{grids.density, grids.mask};
        const std::lock_guard registries(volume::openVdbIoMutex());
        openvdb::io::File file(tmp.string());
        try {
            file.write(out);
            file.close();
        } catch (const openvdb::Exception& e) {
            throw Error(fmt::format("cannot write '{}': {}", path.string(), e.what()));
        }
    });
}

} // namespace veil::voxelize
