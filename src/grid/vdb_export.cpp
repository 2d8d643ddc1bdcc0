#include "grid/vdb_export.h"

#include "base/error.h"
#include "grid/grid_select.h"
#include "grid/vdb_file.h"

#include <fmt/format.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <cmath>

namespace veil::vdb {

namespace {

bool exportable(const openvdb::GridBase& g) {
    return g.isType<openvdb::FloatGrid>() || g.isType<openvdb::DoubleGrid>() ||
           g.isType<openvdb::Vec3SGrid>() || g.isType<openvdb::Vec3DGrid>();
}

template <typename GridT>
void sample(const GridT& grid, const openvdb::CoordBBox& box, double factor, io::DenseGrid& out) {
    constexpr bool vector = openvdb::VecTraits<typename GridT::ValueType>::IsVec;
    out.components = vector ? 3 : 1;
    const std::size_t n = std::size_t(out.dims[0]) * out.dims[1] * out.dims[2];
    out.values.assign(n * out.components, 0.0f);
    const auto acc = grid.getConstAccessor();
    std::size_t i = 0;
    for (int z = 0; z < out.dims[2]; ++z)
        for (int y = 0; y < out.dims[1]; ++y)
            for (int x = 0; x < out.dims[0]; ++x, ++i) {
                typename GridT::ValueType v;
                if (factor == 1.0) {
                    v = acc.getValue(box.min() + openvdb::Coord(x, y, z));
                } else {
                    const openvdb::Vec3d p = box.min().asVec3d() + openvdb::Vec3d(x, y, z) / factor;
                    v = openvdb::tools::BoxSampler::sample(acc, p);
                }
                if constexpr (vector) {
                    for (int c = 0; c < 3; ++c)
                        out.values[i * 3 + c] = static_cast<float>(v[c]);
                } else {
                    out.values[i] = static_cast<float>(v);
                }
            }
}

} // namespace

SampledGrid sampleVdbGrid(const std::filesystem::path& input, const std::string& selector,
                          const std::vector<int>& corners, double resample) {
    VEIL_CHECK(std::isfinite(resample) && resample > 0.0, "'{}': resample {} must be > 0",
               input.string(), resample);
    VEIL_CHECK(corners.empty() || corners.size() == 6,
               "'{}': a box is 6 numbers x0 y0 z0 x1 y1 z1, not {}", input.string(),
               corners.size());
    const openvdb::GridPtrVecPtr grids = volume::readVdbFile(input);
    const vdb::SelectedGrid sel =
        vdb::selectGrid(*grids, input, selector, exportable, "a float or vec3 grid");
    const openvdb::GridBase& grid = *sel.grid;
    const std::string what =
        fmt::format("'{}': grid {} '{}'", input.string(), sel.index, grid.getName());

    openvdb::CoordBBox box;
    if (!corners.empty()) {
        box = openvdb::CoordBBox(openvdb::Coord(corners[0], corners[1], corners[2]),
                                 openvdb::Coord(corners[3], corners[4], corners[5]));
        VEIL_CHECK(!box.empty(),
                   "--box: every minimum must be at most its maximum (got [{} {} "
                   "{}]..[{} {} {}])",
                   corners[0], corners[1], corners[2], corners[3], corners[4], corners[5]);
    } else {
        box = grid.evalActiveVoxelBoundingBox();
        VEIL_CHECK(!box.empty() && grid.activeVoxelCount() > 0,
                   "{} has no active voxels (give --box)", what);
    }

    // ImageData is axis-aligned: each index axis must map onto the same world axis.
    const openvdb::math::Transform& xf = grid.transform();
    VEIL_CHECK(xf.isLinear(), "{}: its transform ({}) is not linear; VTK ImageData cannot hold it",
               what, xf.mapType());
    const openvdb::Vec3d o = xf.indexToWorld(openvdb::Vec3d(0.0));
    io::DenseGrid dense;
    dense.name = grid.getName().empty() ? "values" : grid.getName();
    for (int a = 0; a < 3; ++a) {
        openvdb::Vec3d unit(0.0);
        unit[a] = 1.0;
        const openvdb::Vec3d d = xf.indexToWorld(unit) - o;
        for (int b = 0; b < 3; ++b)
            VEIL_CHECK(b == a || std::abs(d[b]) <= 1e-9 * d.length(),
                       "{}: its transform rotates or shears the index axes; VTK ImageData "
                       "needs an axis-aligned grid",
                       what);
        VEIL_CHECK(d[a] > 0.0,
                   "{}: its transform flips index axis {}; VTK ImageData needs "
                   "positive spacing",
                   what, "xyz"[a]);
        dense.spacing[a] = d[a] / resample;
        const double extent = double(box.max()[a]) - double(box.min()[a]);
        // In double first: a box spanning the int range has 2^32 points along an axis.
        const double n = std::floor(extent * resample + 1e-9) + 1.0;
        VEIL_CHECK(n <= kMaxSampledPoints,
                   "{}: {:.3g} points along {} (index box [{} {} {}]..[{} {} {}]) exceed the "
                   "limit of {:.3g} points (use a smaller --box or a --resample below 1)",
                   what, n, "xyz"[a], box.min().x(), box.min().y(), box.min().z(), box.max().x(),
                   box.max().y(), box.max().z(), kMaxSampledPoints);
        dense.dims[a] = static_cast<int>(n);
    }
    const double points = double(dense.dims[0]) * dense.dims[1] * dense.dims[2];
    VEIL_CHECK(points <= kMaxSampledPoints,
               "{}: {}x{}x{} = {:.3g} points exceed the limit of {:.3g} (use --box or a "
               "--resample below 1)",
               what, dense.dims[0], dense.dims[1], dense.dims[2], points, kMaxSampledPoints);
    const openvdb::Vec3d origin = xf.indexToWorld(box.min());
    for (int a = 0; a < 3; ++a)
        dense.origin[a] = origin[a];

    if (grid.isType<openvdb::FloatGrid>())
        sample(static_cast<const openvdb::FloatGrid&>(grid), box, resample, dense);
    else if (grid.isType<openvdb::DoubleGrid>())
        sample(static_cast<const openvdb::DoubleGrid&>(grid), box, resample, dense);
    else if (grid.isType<openvdb::Vec3SGrid>())
        sample(static_cast<const openvdb::Vec3SGrid&>(grid), box, resample, dense);
    else
        sample(static_cast<const openvdb::Vec3DGrid&>(grid), box, resample, dense);
    SampledGrid out;
    out.dense = std::move(dense);
    out.index = sel.index;
    out.name = grid.getName();
    out.type = gridTypeName(grid);
    for (int a = 0; a < 3; ++a) {
        out.boxMin[a] = box.min()[a];
        out.boxMax[a] = box.max()[a];
    }
    return out;
}

} // namespace veil::vdb
