// `veil export grid.vdb -o grid.vti [--grid NAME|INDEX] [--box x0 y0 z0 x1 y1 z1]
//  [--resample FACTOR]`: one float or vec3 grid of an OpenVDB file as VTK ImageData (.vti,
// vtkXMLImageDataWriter) for ParaView.
//
// Points: the index box (inclusive; default the grid's active bounding box) sampled every
// 1 / FACTOR voxels per axis: FACTOR = 1 gives exactly the voxel values (background where
// inactive), other factors trilinear interpolation in index space
// (openvdb::tools::BoxSampler). Spacing = the grid's voxel size / FACTOR; origin = the world
// position of the box's first index (the grid's own index-to-world transform), so ParaView
// shows the volume where OpenVDB puts it. Transforms that are not axis-aligned scales and
// translations cannot be ImageData and are refused.
#include "app/command_line.h"
#include "app/commands.h"

#include "app/cli_checks.h"
#include "vdb/grid_select.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "io/vtk_export.h"
#include "volume/vdb_file.h"

#include <openvdb/tools/Interpolation.h>

#include <cmath>
#include <iostream>
#include <memory>

namespace veil::app {

namespace fs = std::filesystem;

namespace {

struct ExportArgs {
    std::string input, output, grid;
    std::vector<int> box;
    double resample = 1.0;
};

// Most points written: 2^28 floats are 1 GiB before VTK's own copy.
constexpr double kMaxPoints = 268435456.0;

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

void runExport(const ExportArgs& args) {
    VEIL_CHECK(lowerExtension(args.input) == ".vdb", "input '{}' must be an OpenVDB file (.vdb)",
               args.input);
    VEIL_CHECK(lowerExtension(args.output) == ".vti", "output '{}' must end in .vti", args.output);
    checkOutputPath(args.output, "output", {args.input});
    const openvdb::GridPtrVecPtr grids = volume::readVdbFile(args.input);
    const vdb::SelectedGrid sel =
        vdb::selectGrid(*grids, args.input, args.grid, exportable, "a float or vec3 grid");
    const openvdb::GridBase& grid = *sel.grid;
    const std::string what =
        fmt::format("'{}': grid {} '{}'", args.input, sel.index, grid.getName());

    openvdb::CoordBBox box;
    if (!args.box.empty()) {
        box = openvdb::CoordBBox(openvdb::Coord(args.box[0], args.box[1], args.box[2]),
                                 openvdb::Coord(args.box[3], args.box[4], args.box[5]));
        VEIL_CHECK(!box.empty(),
                   "--box: every minimum must be at most its maximum (got [{} {} "
                   "{}]..[{} {} {}])",
                   args.box[0], args.box[1], args.box[2], args.box[3], args.box[4], args.box[5]);
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
        dense.spacing[a] = d[a] / args.resample;
        const double extent = double(box.max()[a]) - double(box.min()[a]);
        dense.dims[a] = static_cast<int>(std::floor(extent * args.resample + 1e-9)) + 1;
    }
    const double points = double(dense.dims[0]) * dense.dims[1] * dense.dims[2];
    VEIL_CHECK(points <= kMaxPoints,
               "{}: {}x{}x{} = {:.3g} points exceed the limit of {:.3g} (use --box or a "
               "--resample below 1)",
               what, dense.dims[0], dense.dims[1], dense.dims[2], points, kMaxPoints);
    const openvdb::Vec3d origin = xf.indexToWorld(box.min());
    for (int a = 0; a < 3; ++a)
        dense.origin[a] = origin[a];

    if (grid.isType<openvdb::FloatGrid>())
        sample(static_cast<const openvdb::FloatGrid&>(grid), box, args.resample, dense);
    else if (grid.isType<openvdb::DoubleGrid>())
        sample(static_cast<const openvdb::DoubleGrid&>(grid), box, args.resample, dense);
    else if (grid.isType<openvdb::Vec3SGrid>())
        sample(static_cast<const openvdb::Vec3SGrid&>(grid), box, args.resample, dense);
    else
        sample(static_cast<const openvdb::Vec3DGrid&>(grid), box, args.resample, dense);
    dense.fieldData = {{"veil_source", args.input},
                       {"veil_grid", fmt::format("{} '{}' ({})", sel.index, grid.getName(),
                                                 vdb::gridTypeName(grid))},
                       {"veil_version", versionWithCommit()},
                       {"veil_command", commandLine()}};
    io::writeVti(args.output, dense);
    std::cout << fmt::format(
        "wrote {}: grid {} '{}' ({}) of {}, {}x{}x{} points over index box [{} {} {}]..[{} {} "
        "{}], spacing ({:.6g} {:.6g} {:.6g}), origin ({:.6g} {:.6g} {:.6g})\n",
        args.output, sel.index, grid.getName(), vdb::gridTypeName(grid), args.input, dense.dims[0],
        dense.dims[1], dense.dims[2], box.min().x(), box.min().y(), box.min().z(), box.max().x(),
        box.max().y(), box.max().z(), dense.spacing[0], dense.spacing[1], dense.spacing[2],
        dense.origin[0], dense.origin[1], dense.origin[2]);
}

} // namespace

void addExportCommand(CLI::App& app) {
    auto args = std::make_shared<ExportArgs>();
    CLI::App* cmd = app.add_subcommand(
        "export", "Export a float or vec3 grid of a .vdb to VTK ImageData (.vti) for ParaView");
    cmd->add_option("input", args->input, "OpenVDB file (.vdb)")->required();
    cmd->add_option("-o,--output", args->output, "Output VTK image (.vti)")->required();
    cmd->add_option("--grid", args->grid,
                    "Grid name or index (default: the first float or vec3 grid)");
    cmd->add_option("--box", args->box,
                    "Index box x0 y0 z0 x1 y1 z1, inclusive (default: the active bounding box)")
        ->expected(6);
    cmd->add_option("--resample", args->resample,
                    "Points per voxel per axis: 1 = the voxel values (default), 0.5 = every "
                    "other voxel, 2 = twice as dense (trilinear)")
        ->check(finiteRange(1e-3, 64.0));
    cmd->callback([args] { runExport(*args); });
}

} // namespace veil::app
