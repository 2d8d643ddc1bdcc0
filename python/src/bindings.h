// The pieces of the `veil` extension module (_veil), one function per binding file, and the
// Python-side scene (a JSON document kept with the parsed scene) they share.
#pragma once

#include "convert.h"
#include "errors.h"
#include "gpu/context.h"
#include "scene/scene_document.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace veil::python {

// veil.Scene: the scene document (with every set() applied) and the scene parsed from it.
// Each change re-parses, so a bad value fails at set() with the message `--set` gives and
// leaves the scene as it was.
struct PyScene {
    nlohmann::json doc;
    std::filesystem::path baseDir; // relative file paths in the document resolve against it
    std::string source;            // in messages: the file as given, or "<scene>"
    std::filesystem::path file;    // absolute; empty for a scene made from a dict
    std::shared_ptr<const scene::Scene> parsed;

    static PyScene load(const std::filesystem::path& path,
                        const std::vector<std::string>& overrides);
    static PyScene fromDict(py::handle dict, const std::filesystem::path& baseDir);
    void set(const std::string& key, py::handle value);
    void reparse(nlohmann::json candidate);

private:
    void reparseChecked(nlohmann::json candidate);
};

// A Scene, a path to a scene file (a .vdb path: framed like `veil render file.vdb`) or a
// dict, as render() and voxelize() take it.
PyScene sceneArgument(py::handle value);

// Runs f with the Renderer's GL context current, under its lock, the GIL released.
void withRendererContext(py::handle renderer,
                         const std::function<void(const gpu::ContextInfo&)>& f);

void bindScene(py::module_& m);
void bindImages(py::module_& m);   // read_image, write_image, compare, heat_map, tonemap
void bindRenderer(py::module_& m); // Renderer, techniques
void bindFrames(py::module_& m);   // Renderer.frames()'s iterator
void bindData(py::module_& m);     // vdb_info, export_vti, voxelize, Suite

} // namespace veil::python
