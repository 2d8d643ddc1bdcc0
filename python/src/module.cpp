// The extension module veil._veil; the package veil (python/veil/__init__.py) re-exports it.
#include "bindings.h"
#include "errors.h"

namespace py = pybind11;

PYBIND11_MODULE(_veil, m) {
    m.doc() = "Veil's libraries for Python: scenes, headless rendering, image comparison, "
              "OpenVDB and voxelization (docs/python.md).";
    m.attr("__version__") = VEIL_VERSION;
    veil::python::registerErrors(m);
    veil::python::bindScene(m);
    veil::python::bindImages(m);
    veil::python::bindRenderer(m);
    veil::python::bindData(m);
}
