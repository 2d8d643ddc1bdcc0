// Arguments of the module's functions: any Python object reaches the binding (so a wrong type
// is a veil.TypeError naming the argument and what it accepts, not pybind11's overload dump),
// while help() shows the type each accepts (`width: int | None`, not `object`).
#pragma once

#include "errors.h"

#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

namespace veil::python {

inline int anyObject(PyObject*) { return 1; }

#define VEIL_PY_ARG(Name)                                                                          \
    struct Name : py::object {                                                                     \
        PYBIND11_OBJECT_DEFAULT(Name, object, anyObject)                                           \
    }

VEIL_PY_ARG(PathArg);     // str | os.PathLike
VEIL_PY_ARG(SceneArg);    // Scene | str | os.PathLike | dict
VEIL_PY_ARG(ImageArg);    // numpy.ndarray | str | os.PathLike
VEIL_PY_ARG(ArrayArg);    // numpy.ndarray
VEIL_PY_ARG(ValueArg);    // a JSON value
VEIL_PY_ARG(DictArg);     // dict
VEIL_PY_ARG(IntArg);      // int
VEIL_PY_ARG(OptIntArg);   // int | None
VEIL_PY_ARG(FloatArg);    // float
VEIL_PY_ARG(BoolArg);     // bool
VEIL_PY_ARG(StrArg);      // str
VEIL_PY_ARG(OptStrArg);   // str | None
VEIL_PY_ARG(StrListArg);  // list[str]
VEIL_PY_ARG(MetricArg);   // str | list[str]
VEIL_PY_ARG(GridArg);     // str | int | None
VEIL_PY_ARG(IntListArg);  // list[int]
VEIL_PY_ARG(RendererArg); // Renderer | None
VEIL_PY_ARG(OptPathArg);  // str | os.PathLike | None
VEIL_PY_ARG(OptArrayArg); // numpy.ndarray | None

#undef VEIL_PY_ARG

// The conversions: `name` is the argument as the caller wrote it ("width", "aovs").
std::string typeName(py::handle value);
long long toInt(py::handle value, const std::string& name);
std::optional<long long> toOptInt(py::handle value, const std::string& name);
double toFloat(py::handle value, const std::string& name);
bool toBool(py::handle value, const std::string& name);
std::string toStr(py::handle value, const std::string& name);
std::optional<std::string> toOptStr(py::handle value, const std::string& name);
// A list or tuple of str (a single str is a list of one when `single` is true).
std::vector<std::string> toStrList(py::handle value, const std::string& name, bool single);
std::vector<int> toIntList(py::handle value, const std::string& name);

} // namespace veil::python

#define VEIL_PY_ARG_NAME(Name, Shown)                                                              \
    template <>                                                                                    \
    struct pybind11::detail::handle_type_name<veil::python::Name> {                                \
        static constexpr auto name = const_name(Shown);                                            \
    }

VEIL_PY_ARG_NAME(PathArg, "str | os.PathLike");
VEIL_PY_ARG_NAME(SceneArg, "Scene | str | os.PathLike | dict");
VEIL_PY_ARG_NAME(ImageArg, "numpy.ndarray | str | os.PathLike");
VEIL_PY_ARG_NAME(ArrayArg, "numpy.ndarray");
VEIL_PY_ARG_NAME(ValueArg, "str | int | float | bool | list | dict | None");
VEIL_PY_ARG_NAME(DictArg, "dict");
VEIL_PY_ARG_NAME(IntArg, "int");
VEIL_PY_ARG_NAME(OptIntArg, "int | None");
VEIL_PY_ARG_NAME(FloatArg, "float");
VEIL_PY_ARG_NAME(BoolArg, "bool");
VEIL_PY_ARG_NAME(StrArg, "str");
VEIL_PY_ARG_NAME(OptStrArg, "str | None");
VEIL_PY_ARG_NAME(StrListArg, "list[str]");
VEIL_PY_ARG_NAME(MetricArg, "str | list[str]");
VEIL_PY_ARG_NAME(GridArg, "str | int | None");
VEIL_PY_ARG_NAME(IntListArg, "list[int]");
VEIL_PY_ARG_NAME(RendererArg, "Renderer | None");
VEIL_PY_ARG_NAME(OptPathArg, "str | os.PathLike | None");
VEIL_PY_ARG_NAME(OptArrayArg, "numpy.ndarray | None");

#undef VEIL_PY_ARG_NAME
