// `veil export grid.vdb -o grid.vti [--grid NAME|INDEX] [--box x0 y0 z0 x1 y1 z1]
//  [--resample FACTOR] [--frame N | --frames A-B[:S]]`: one float or vec3 grid of an OpenVDB
// file as VTK ImageData (.vti, vtkXMLImageDataWriter) for ParaView. With --frame/--frames the
// input is a file sequence (fire.####.vdb, fire_#.vdb, ...) and each frame goes to the output
// with its frame number filled in (out.####.vti); every frame's file is checked to exist
// before anything is written, and each output is written atomically.
//
// Points: the index box (inclusive; default the grid's active bounding box) sampled every
// 1 / FACTOR voxels per axis: FACTOR = 1 gives exactly the voxel values (background where
// inactive), other factors trilinear interpolation in index space
// (openvdb::tools::BoxSampler). Spacing = the grid's voxel size / FACTOR; origin = the world
// position of the box's first index (the grid's own index-to-world transform), so ParaView
// shows the volume where OpenVDB puts it. Transforms that are not axis-aligned scales and
// translations cannot be ImageData and are refused.
#include "app/commands.h"
#include "app/shared_options.h"

#include "app/cli_checks.h"
#include "app/shared_options.h"
#include "grid/vdb_export.h"

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
    FrameOptions frames;
};

void exportOne(const ExportArgs& args, const std::string& input, const std::string& output) {
    vdb::SampledGrid sampled = vdb::sampleVdbGrid(input, args.grid, args.box, args.resample);
    io::DenseGrid& dense = sampled.dense;
    dense.fieldData = {
        {"veil_source", input},
        {"veil_grid", fmt::format("{} '{}' ({})", sampled.index, sampled.name, sampled.type)},
        {"veil_version", versionWithCommit()},
        {"veil_command", commandLine()}};
    io::writeVti(output, dense);
    std::cout << fmt::format(
        "wrote {}: grid {} '{}' ({}) of {}, {}x{}x{} points over index box [{} {} {}]..[{} {} "
        "{}], spacing ({:.6g} {:.6g} {:.6g}), origin ({:.6g} {:.6g} {:.6g})\n",
        output, sampled.index, sampled.name, sampled.type, input, dense.dims[0], dense.dims[1],
        dense.dims[2], sampled.boxMin[0], sampled.boxMin[1], sampled.boxMin[2], sampled.boxMax[0],
        sampled.boxMax[1], sampled.boxMax[2], dense.spacing[0], dense.spacing[1], dense.spacing[2],
        dense.origin[0], dense.origin[1], dense.origin[2]);
}

void runExport(const ExportArgs& args) {
    VEIL_CHECK(lowerExtension(args.input) == ".vdb", "input '{}' must be an OpenVDB file (.vdb)",
               args.input);
    if (lowerExtension(args.output) != ".vti")
        usageError(fmt::format("output '{}' must end in .vti", args.output));
    io::requireVti(args.output);
    const std::vector<int> frames = args.frames.list();
    if (frames.empty()) {
        const fs::path input = inputForFrame(args.input, std::nullopt, "input");
        checkOutputPath(args.output, "output", {input});
        exportOne(args, input.string(), args.output);
        return;
    }
    // Every input and output checked before the first frame is written.
    checkFrameInputs(args.input, frames);
    std::vector<fs::path> inputs, outputs;
    for (int f : frames) {
        inputs.push_back(inputForFrame(args.input, f, "input"));
        outputs.push_back(outputForFrame(args.output, f, frames.size() == 1, "output"));
    }
    for (const fs::path& out : outputs)
        checkOutputPath(out, "output", inputs);
    for (std::size_t i = 0; i < frames.size(); ++i)
        exportOne(args, inputs[i].string(), outputs[i].string());
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
    args->frames.add(*cmd, "the input sequence");
    cmd->callback([args] { runExport(*args); });
}

} // namespace veil::app
