// The extension module veil._veil; the package veil (python/veil/__init__.py) re-exports it.
#include "bindings.h"

#include "base/error.h"

namespace py = pybind11;

PYBIND11_MODULE(_veil, m) {
    m.doc() = "Veil's libraries for Python: scenes, headless rendering, image comparison, "
              "OpenVDB and voxelization (docs/python.md).";
    m.attr("__version__") = VEIL_VERSION;
    static py::exception<veil::Error> error(m, "Error", PyExc_RuntimeError);
    error.attr("__doc__") = "What failed, in the one line `veil` prints (veil: error: ...).";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const veil::Error& e) {
            PyErr_SetString(error.ptr(), e.what());
        } catch (const nlohmann::json::exception& e) {
            PyErr_SetString(error.ptr(), e.what());
        } catch (const std::filesystem::filesystem_error& e) {
            PyErr_SetString(error.ptr(), e.what());
        }
    });
    veil::python::bindScene(m);
    veil::python::bindImages(m);
    veil::python::bindRenderer(m);
    veil::python::bindData(m);
}
