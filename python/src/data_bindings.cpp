// veil.vdb_info, export_vti, voxelize and the regression suite runner (veil.Suite).
#include "bindings.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "gpu/context.h"
#include "grid/vdb_export.h"
#include "grid/vdb_info.h"
#include "io/vtk_export.h"
#include "regress/runner.h"
#include "regress/suite.h"
#include "voxelize/pipeline.h"

#include <pybind11/stl.h>

#include <optional>

namespace veil::python {

namespace fs = std::filesystem;

namespace {

// An input file that must exist: veil.FileNotFoundError naming it and the argument.
fs::path inputFile(py::handle value, const std::string& what) {
    const fs::path path = toPath(value, what);
    std::error_code ec;
    if (!fs::exists(path, ec))
        throw PyError(ErrorKind::FileNotFound,
                      fmt::format("{}: '{}' does not exist", what, printable(path.string(), 500)),
                      path.string());
    return path;
}

// A grid selector: a name, an index or None (the default grid).
std::string gridSelector(py::handle grid) {
    if (grid.is_none()) return {};
    if (py::isinstance<py::str>(grid)) return grid.cast<std::string>();
    return std::to_string(toInt(grid, "grid"));
}

py::list vdbInfo(const PathArg& pathArg, const GridArg& grid) {
    const fs::path path = inputFile(pathArg, "vdb_info(path)");
    const std::string selector = gridSelector(grid);
    const vdb::FileInfo file =
        classified(ErrorKind::Value, [&] { return vdb::describeVdbFile(path, selector); });
    py::list out;
    for (const vdb::GridInfo& g : file.grids) {
        nlohmann::json j = {{"index", g.index},
                            {"name", g.name},
                            {"type", g.type},
                            {"class", g.gridClass},
                            {"active_voxels", g.activeVoxels},
                            {"value_range", g.valueRange},
                            {"index_min", g.indexMin},
                            {"index_max", g.indexMax},
                            {"voxel_size", g.voxelSize},
                            {"world_min", g.worldMin},
                            {"world_max", g.worldMax},
                            {"transform", g.transform},
                            {"grid_bytes", g.gridBytes},
                            {"gpu_bytes", g.gpuBytes}};
        if (g.hasRange) {
            j["min"] = g.min;
            j["max"] = g.max;
        }
        j["metadata"] = nlohmann::json::object();
        for (const auto& meta : g.metadata)
            j["metadata"][meta.name] = {{"type", meta.type}, {"value", meta.value}};
        out.append(toPython(j));
    }
    return out;
}

py::dict exportVti(const PathArg& vdbArg, const PathArg& vtiArg, const GridArg& grid,
                   const IntListArg& boxArg, const FloatArg& resampleArg) {
    const fs::path input = inputFile(vdbArg, "export_vti(vdb)");
    const fs::path output = toPath(vtiArg, "export_vti(vti)");
    const std::vector<int> box = boxArg.is_none() ? std::vector<int>{} : toIntList(boxArg, "box");
    const double resample = toFloat(resampleArg, "resample");
    VEIL_PY_CHECK(ErrorKind::Value, lowerExtension(input.string()) == ".vdb",
                  "export_vti(vdb): '{}' must be an OpenVDB file (.vdb)",
                  printable(input.string(), 500));
    VEIL_PY_CHECK(ErrorKind::Value, lowerExtension(output.string()) == ".vti",
                  "export_vti(vti): '{}' must end in .vti", printable(output.string(), 500));
    io::requireVti(output);
    const std::string selector = gridSelector(grid);
    const vdb::SampledGrid s = classified(ErrorKind::Value, [&] {
        checkOutputPath(output, "output", {input});
        return vdb::sampleVdbGrid(input, selector, box, resample);
    });
    io::writeVti(output, s.dense);
    const nlohmann::json j = {
        {"index", s.index},     {"name", s.name},           {"type", s.type},
        {"dims", s.dense.dims}, {"origin", s.dense.origin}, {"spacing", s.dense.spacing},
        {"box_min", s.boxMin},  {"box_max", s.boxMax},      {"components", s.dense.components}};
    return toPython(j);
}

py::array_t<bool> voxelize(const SceneArg& source, const IntArg& resArg, const IntArg& slicesArg,
                           const StrArg& methodArg, const BoolArg& solidArg,
                           const BoolArg& localArg, const BoolArg& perspectiveArg,
                           const StrArg& cameraArg, const OptPathArg& outputArg,
                           const FloatArg& smoothArg, const RendererArg& renderer) {
    const long long res = toInt(resArg, "res"), slices = toInt(slicesArg, "slices");
    const std::string methodName = toStr(methodArg, "method"), camera = toStr(cameraArg, "camera");
    const bool solid = toBool(solidArg, "solid"), local = toBool(localArg, "local"),
               perspective = toBool(perspectiveArg, "perspective");
    const double smooth = toFloat(smoothArg, "smooth");
    VEIL_PY_CHECK(ErrorKind::Value, res >= 1 && res <= 8192, "res {} not in range [1, 8192]", res);
    VEIL_PY_CHECK(ErrorKind::Value, slices >= 0 && slices <= 65536,
                  "slices {} not in range [0, 65536]", slices);
    VEIL_PY_CHECK(ErrorKind::Value, std::isfinite(smooth) && smooth >= 0.0 && smooth <= 64.0,
                  "smooth {} not in range [0, 64]", smooth);
    const voxelize::Method method = classified(ErrorKind::Value, [&] {
        return voxelize::parseMethod(methodName.empty() ? (solid ? "raster" : "conservative")
                                                        : methodName);
    });
    fs::path output;
    if (!outputArg.is_none()) {
        output = toPath(outputArg, "voxelize(output)");
        VEIL_PY_CHECK(ErrorKind::Value, lowerExtension(output.string()) == ".vdb",
                      "voxelize(output): '{}' must end in .vdb", printable(output.string(), 500));
    }
    // A mesh file is voxelized alone; anything else is a scene.
    bool mesh = false;
    std::string sourceName = "<scene>";
    std::shared_ptr<const scene::Scene> scene;
    if (isPathLike(source) && voxelize::isMeshFile(toPath(source, "voxelize").string())) {
        const fs::path path = toPath(source, "voxelize");
        VEIL_PY_CHECK(ErrorKind::Value, !perspective, "'{}' is a mesh: perspective needs a scene",
                      path.string());
        scene = std::make_shared<scene::Scene>(
            classified(ErrorKind::Value, [&] { return voxelize::sceneForMesh(path); }));
        mesh = true;
        sourceName = path.string();
    } else {
        PyScene s = sceneArgument(source);
        scene = s.parsed;
        sourceName = s.source;
    }
    std::vector<fs::path> inputs;
    if (!scene->sourcePath.empty()) inputs.push_back(scene->sourcePath);
    for (const scene::VolumeRef& v : scene->volumes)
        if (!v.path.empty()) inputs.push_back(v.path);
    voxelize::Voxelization voxels = classified(ErrorKind::Value, [&] {
        if (!output.empty()) checkOutputPath(output, "output", inputs);
        return voxelize::prepareVoxelization(
            *scene, {static_cast<int>(res), static_cast<int>(slices), perspective, camera}, mesh);
    });
    auto run = [&](const gpu::ContextInfo& info) {
        voxelize::fillGrid(voxels, info, {method, solid, local});
    };
    if (renderer.is_none()) {
        py::gil_scoped_release release;
        gpu::HeadlessContext own(gpu::HeadlessOptions{});
        run(own.info());
    } else {
        withRendererContext(renderer, run);
    }
    const voxelize::SliceMap& filled = voxels.grid;
    if (!output.empty()) {
        voxelize::VdbOptions options;
        options.smoothing = smooth;
        voxelize::writeVdb(output, voxelize::toVdbNamed(filled, options, sourceName));
    }
    py::array_t<bool> out({filled.slices, filled.height, filled.width});
    auto v = out.mutable_unchecked<3>();
    for (int s = 0; s < filled.slices; ++s)
        for (int y = 0; y < filled.height; ++y)
            for (int x = 0; x < filled.width; ++x)
                v(s, y, x) = filled.get(x, y, s);
    return out;
}

struct PySuite {
    regress::Suite suite;
};

} // namespace

void bindData(py::module_& m) {
    m.def("vdb_info", &vdbInfo, py::arg("path"), py::arg("grid") = py::none(),
          R"doc(What a .vdb file holds, one dict per grid (as `veil info file.vdb`).

Keys: index, name, type, class, active_voxels, value_range (text), min/max
(over the active values; vectors: their lengths), index_min/index_max (active
bounding box), voxel_size, world_min/world_max, transform, grid_bytes,
gpu_bytes (what a render would upload), metadata {name: {type, value}}.
grid: a name or index to describe one grid only.)doc");
    m.def("export_vti", &exportVti, py::arg("vdb"), py::arg("vti"), py::arg("grid") = py::none(),
          py::arg("box") = std::vector<int>{}, py::arg("resample") = 1.0,
          R"doc(Write a float or vec3 grid of a .vdb as VTK ImageData (.vti), as `veil export`.

grid: name or index (default the first float or vec3 grid); box: index box
[x0, y0, z0, x1, y1, z1] inclusive (default the active bounding box); resample:
points per voxel per axis (1: the voxel values; else trilinear). Returns the
grid's index, name, type, dims, origin, spacing and the box.)doc");
    m.def("voxelize", &voxelize, py::arg("source"), py::arg("res") = 64, py::arg("slices") = 0,
          py::arg("method") = "", py::arg("solid") = false, py::arg("local") = false,
          py::arg("perspective") = false, py::arg("camera") = "", py::arg("output") = py::none(),
          py::arg("smooth") = 0.0, py::arg("renderer") = py::none(),
          R"doc(Slice-map voxelization on the GPU, as `veil voxelize`.

source: a Scene, a scene file, or a mesh file (.obj, .ply, .glb, .gltf: cubic
voxels fitted to its bounds). res columns per side, slices per column (0: res),
method raster | conservative | three-axis | compute (default conservative,
raster when solid). Returns the slice map as a bool array [slice, y, x]
(orthographic grids: world z, y, x). output: also write the OpenVDB grids
"density" and "mask" (.vdb; smooth: Gaussian width in voxels). renderer: use
its GL context instead of a new one.)doc");

    py::class_<PySuite>(m, "Suite",
                        R"doc(An image regression suite (docs/regression.md), checked as a whole.

Suite(path, update=False); .names lists the cases; run(name, renderer, output)
renders one case and compares it with its reference (veil.testing.regress_cases
makes pytest parameters of them).)doc")
        .def(py::init([](const PathArg& path, const BoolArg& update) {
                 const fs::path file = inputFile(path, "Suite(path)");
                 const bool u = toBool(update, "update");
                 // With update (VEIL_UPDATE_REFERENCES=1 in veil.testing), as `veil regress
                 // --update`: missing reference folders inside the suite's folder are made
                 // and every reference path checked before anything renders.
                 return PySuite{classified(ErrorKind::Value, [&] {
                     regress::Suite suite = regress::loadSuite(file, u);
                     if (u) regress::prepareReferenceFolders(suite);
                     return suite;
                 })};
             }),
             py::arg("path"), py::arg("update") = false)
        .def_property_readonly("name", [](const PySuite& s) { return s.suite.name; })
        .def_property_readonly("file", [](const PySuite& s) { return s.suite.file.string(); })
        .def_property_readonly("names",
                               [](const PySuite& s) {
                                   std::vector<std::string> out;
                                   for (const auto& c : s.suite.cases)
                                       out.push_back(c.name);
                                   return out;
                               })
        .def(
            "run",
            [](const PySuite& s, const StrArg& nameArg, const RendererArg& renderer,
               const PathArg& output, const BoolArg& update) {
                const std::string name = toStr(nameArg, "Suite.run(name)");
                const regress::RegressCase* k = nullptr;
                for (const auto& c : s.suite.cases)
                    if (c.name == name) k = &c;
                if (!k)
                    throw PyError(ErrorKind::Key,
                                  fmt::format("{}: no case '{}'", s.suite.file.string(),
                                              printable(name, 200)));
                regress::RunOptions options;
                options.output = toPath(output, "Suite.run(output)");
                options.update = toBool(update, "update");
                regress::CaseResult r;
                withRendererContext(renderer, [&](const gpu::ContextInfo& info) {
                    r = regress::runCase(*k, info, options);
                });
                return toPython(r.toJson());
            },
            py::arg("name"), py::arg("renderer"), py::arg("output"), py::arg("update") = false,
            R"doc(Render case `name` with the renderer's context and compare it; returns the report's
case dict (passed, metrics, error, images relative to `output`).)doc");
}

} // namespace veil::python
