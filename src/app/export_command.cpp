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
#include "vdb/vdb_export.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "io/vtk_export.h"

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

void runExport(const ExportArgs& args) {
    VEIL_CHECK(lowerExtension(args.input) == ".vdb", "input '{}' must be an OpenVDB file (.vdb)",
               args.input);
    if (lowerExtension(args.output) != ".vti")
        usageError(fmt::format("output '{}' must end in .vti", args.output));
    checkOutputPath(args.output, "output", {args.input});
    vdb::SampledGrid sampled = vdb::sampleVdbGrid(args.input, args.grid, args.box, args.resample);
    io::DenseGrid& dense = sampled.dense;
    dense.fieldData = {
        {"veil_source", args.input},
        {"veil_grid", fmt::format("{} '{}' ({})", sampled.index, sampled.name, sampled.type)},
        {"veil_version", versionWithCommit()},
        {"veil_command", commandLine()}};
    io::writeVti(args.output, dense);
    std::cout << fmt::format(
        "wrote {}: grid {} '{}' ({}) of {}, {}x{}x{} points over index box [{} {} {}]..[{} {} "
        "{}], spacing ({:.6g} {:.6g} {:.6g}), origin ({:.6g} {:.6g} {:.6g})\n",
        args.output, sampled.index, sampled.name, sampled.type, args.input, dense.dims[0],
        dense.dims[1], dense.dims[2], sampled.boxMin[0], sampled.boxMin[1], sampled.boxMin[2],
        sampled.boxMax[0], sampled.boxMax[1], sampled.boxMax[2], dense.spacing[0], dense.spacing[1],
        dense.spacing[2], dense.origin[0], dense.origin[1], dense.origin[2]);
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
