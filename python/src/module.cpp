// The extension module veil._veil; the package veil (python/veil/__init__.py) re-exports it.
#include "bindings.h"
#include "errors.h"

namespace py = pybind11;

PYBIND11_MODULE(_veil, m) {
    m.doc() = "Veil's libraries for Python: scenes, headless rendering, image comparison, "
              "OpenVDB and voxelization (docs/python.md).";
    m.attr("__version__") = VEIL_VERSION;
    // Classes and functions are made while the module calls itself "veil", the package that
    // re-exports them, so that signatures, help() and tracebacks name veil.Scene, not
    // veil._veil.Scene; the import system needs the real name back before this returns.
    const py::object name = m.attr("__name__");
    m.attr("__name__") = "veil";
    veil::python::registerErrors(m);
    veil::python::bindScene(m);
    veil::python::bindImages(m);
    veil::python::bindRenderer(m);
    veil::python::bindFrames(m);
    veil::python::bindData(m);
    m.attr("__name__") = name;
}
