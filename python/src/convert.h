// Conversions between the libraries' types and Python's: JSON values and Python objects,
// float images and NumPy arrays, paths. Shared by the binding files of the module.
#pragma once

#include "args.h"
#include "base/image.h"

#include <nlohmann/json.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <filesystem>
#include <string>

namespace veil::python {

namespace py = pybind11;

// JSON -> Python: objects become dicts, arrays lists, numbers int or float.
py::object toPython(const nlohmann::json& value);
// Python -> JSON: dicts with str keys, lists and tuples, str, bool, int, float, None and NumPy
// scalars and arrays, nested at most scene::kMaxJsonDepth levels (the JSON parser's cap: a
// deeper value, or one that contains itself, is refused before anything recurses past it).
// Anything else is a veil.ValueError or TypeError "<what>: <JSON pointer>: <problem>".
nlohmann::json fromPython(py::handle value, const std::string& what);

// An image as a float32 array that owns its pixels (no copy): H x W x C, or H x W for one
// channel (`squeeze`).
py::array_t<float> toArray(ImageF image, bool squeeze = true);
// The first `channels` channels of an owned image as a view (no copy), H x W x channels
// (H x W when channels is 1): strides skip the others.
py::array_t<float> channelView(const py::array_t<float>& whole, int first, int channels);
// An array of H x W or H x W x C (C = 1..4) numbers as a float image (copied, converted to
// float32). Other shapes and non-numeric arrays are a veil::Error naming `what`.
ImageF fromArray(py::handle array, const std::string& what);

// A str or os.PathLike as a path; anything else is a veil::Error naming `what`.
std::filesystem::path toPath(py::handle value, const std::string& what);
bool isPathLike(py::handle value);

} // namespace veil::python
