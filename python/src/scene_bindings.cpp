// veil.Scene (docs/python.md).
#include "bindings.h"

#include "base/error.h"
#include "base/text.h"
#include "grid/vdb_scene.h"
#include "oit/technique.h"

#include <fmt/ranges.h>
#include <pybind11/stl.h>

namespace veil::python {

namespace fs = std::filesystem;

PyScene PyScene::load(const fs::path& path, const std::vector<std::string>& overrides) {
    std::error_code ec;
    if (!fs::exists(path, ec))
        throw PyError(
            ErrorKind::FileNotFound,
            fmt::format("cannot open scene file '{}': no such file", printable(path.string(), 500)),
            path.string());
    PyScene s;
    s.source = path.string();
    s.file = fs::absolute(path);
    s.baseDir = s.file.parent_path();
    nlohmann::json doc = classified(ErrorKind::Value, [&] {
        nlohmann::json d = scene::readSceneDocument(path);
        scene::applySceneOverrides(d, overrides, s.source);
        return d;
    });
    s.reparse(std::move(doc));
    return s;
}

PyScene PyScene::fromDict(py::handle dict, const fs::path& baseDir) {
    VEIL_PY_CHECK(ErrorKind::Type, py::isinstance<py::dict>(dict),
                  "Scene(doc): expected a dict (a scene document), got {}", typeName(dict));
    PyScene s;
    s.source = "<scene>";
    s.baseDir = baseDir.empty() ? fs::current_path() : fs::absolute(baseDir);
    s.reparse(fromPython(dict, "Scene(doc)"));
    return s;
}

void PyScene::reparse(nlohmann::json candidate) {
    // A scene that does not parse is a bad value (veil.ValueError; an unknown key a
    // veil.KeyError, a missing file a veil.FileNotFoundError), with the command line's line.
    classified(ErrorKind::Value, [&] { reparseChecked(std::move(candidate)); });
}

void PyScene::reparseChecked(nlohmann::json candidate) {
    auto parsedScene =
        std::make_shared<scene::Scene>(scene::parseScene(candidate, baseDir, source));
    // The scene's OIT technique and its properties, checked as `veil render` checks them
    // before it renders.
    const scene::RenderSettings& r = parsedScene->render;
    const auto& registry = oit::Registry::instance();
    VEIL_CHECK(registry.find(r.oit), "{}/type: unknown OIT technique '{}' (known: {})", r.oitWhere,
               r.oit, fmt::join(registry.names(), ", "));
    registry.resolve(r.oit, r.oitProperties, r.oitWhere);
    parsedScene->sourcePath = file;
    parsed = std::move(parsedScene);
    doc = std::move(candidate);
}

void PyScene::set(const std::string& key, py::handle value) {
    VEIL_PY_CHECK(ErrorKind::Value, key.find('=') == std::string::npos,
                  "Scene.set(key): '{}': a key has no '=' (set(key, value))", printable(key, 200));
    // The `--set key=value` string: a str value as typed on a command line (JSON when it
    // parses as JSON, else a string), anything else as its JSON text.
    const std::string text =
        py::isinstance<py::str>(value)
            ? value.cast<std::string>()
            : fromPython(value, fmt::format("Scene.set('{}', value)", printable(key, 100))).dump();
    nlohmann::json candidate = doc;
    classified(ErrorKind::Value,
               [&] { scene::applySceneOverrides(candidate, {key + "=" + text}, source); });
    reparse(std::move(candidate));
}

PyScene sceneArgument(py::handle value) {
    if (py::isinstance<PyScene>(value)) return value.cast<PyScene>();
    if (py::isinstance<py::dict>(value)) return PyScene::fromDict(value, {});
    VEIL_PY_CHECK(ErrorKind::Type, isPathLike(value),
                  "scene: expected a veil.Scene, a path (str or os.PathLike) or a dict, got {}",
                  typeName(value));
    const fs::path path = toPath(value, "scene");
    if (lowerExtension(path.string()) == ".vdb") {
        // A bare density volume, framed as `veil render file.vdb` frames it.
        vdb::VdbScene v =
            classified(ErrorKind::Value, [&] { return vdb::sceneForVdb(path, "", {}); });
        PyScene s;
        s.source = path.string();
        s.file = fs::absolute(path);
        s.baseDir = s.file.parent_path();
        s.parsed = std::make_shared<scene::Scene>(std::move(v.scene));
        return s;
    }
    return PyScene::load(path, {});
}

void bindScene(py::module_& m) {
    // The converter Scene() and Scene.set() use, alone: the JSON text of a value, for the
    // randomized tests of the conversion (tests/python/test_errors.py).
    m.def(
        "_json_text", [](const ValueArg& value) { return fromPython(value, "value").dump(); },
        py::arg("value"));
    py::class_<PyScene>(
        m, "Scene",
        R"doc(A scene: the JSON document of docs/scene-format.md and the scene parsed from it.

Scene(doc, base_dir=None) parses a dict (relative file paths resolve against
base_dir, default the current folder); Scene.load(path) reads a scene file.
Every change is checked at once, with the messages `veil render --set` gives.)doc")
        .def(py::init([](const DictArg& doc, const OptPathArg& baseDir) {
                 return PyScene::fromDict(doc, baseDir.is_none() ? fs::path()
                                                                 : toPath(baseDir, "base_dir"));
             }),
             py::arg("doc"), py::arg("base_dir") = py::none(),
             "Parse a scene document (a dict as the JSON scene file holds it).")
        .def_static(
            "load",
            [](const PathArg& path, const StrListArg& overrides) {
                return PyScene::load(toPath(path, "Scene.load(path)"),
                                     overrides.is_none()
                                         ? std::vector<std::string>{}
                                         : toStrList(overrides, "Scene.load(overrides)", false));
            },
            py::arg("path"), py::arg("overrides") = py::none(),
            R"doc(Read a scene file (JSON, comments allowed).

overrides: "key=value" strings applied first, exactly as `veil render --set`.)doc")
        .def(
            "set",
            [](PyScene& s, const StrArg& key, const ValueArg& value) -> PyScene& {
                s.set(toStr(key, "Scene.set(key)"), value);
                return s;
            },
            py::arg("key"), py::arg("value"),
            R"doc(Override a scene value by dotted path, as `--set key=value` does.

scene.set("render.oit.type", "moment-p6"); scene.set("lights.0.intensity", 40).
A str value is read as on a command line (JSON when it parses as JSON, else a
string); other values as JSON. An unknown key raises veil.KeyError, a bad
value veil.ValueError (both ValueErrors, and veil.Errors), with the command
line's message, and leave the scene unchanged. Returns the scene, so calls
chain.)doc")
        .def(
            "to_dict", [](const PyScene& s) { return py::dict(toPython(s.doc)); },
            "The scene document with every set() applied, as a dict.")
        .def(
            "copy", [](const PyScene& s) { return s; }, "An independent copy.")
        .def_property_readonly(
            "path",
            [](const PyScene& s) -> py::object {
                if (s.file.empty()) return py::none();
                return py::module_::import("pathlib").attr("Path")(s.file.string());
            },
            "The scene file (absolute), or None for a scene made from a dict.")
        .def_property_readonly(
            "cameras",
            [](const PyScene& s) {
                std::vector<std::string> names;
                for (const auto& c : s.parsed->cameras)
                    names.push_back(c.name);
                return names;
            },
            "Camera names.")
        .def_property_readonly(
            "size",
            [](const PyScene& s) {
                return std::make_pair(s.parsed->render.width, s.parsed->render.height);
            },
            "(width, height) of render.width / render.height.")
        .def("__repr__", [](const PyScene& s) {
            return fmt::format("veil.Scene('{}', {} objects, {} volumes, oit {})", s.source,
                               s.parsed->objects.size(), s.parsed->volumes.size(),
                               s.parsed->render.oit);
        });
}

} // namespace veil::python
