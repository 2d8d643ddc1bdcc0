#include "args.h"

#include "base/text.h"

namespace veil::python {

namespace {

[[noreturn]] void wrongType(py::handle value, const std::string& name, const char* expected) {
    throw PyError(ErrorKind::Type,
                  fmt::format("{}: expected {}, got {}", name, expected, typeName(value)));
}

bool isBool(py::handle value) { return PyBool_Check(value.ptr()); }

bool isIntLike(py::handle value) {
    // int and NumPy's integers (which have __index__), never bool.
    return !isBool(value) && !PyFloat_Check(value.ptr()) &&
           (PyLong_Check(value.ptr()) ||
            (py::hasattr(value, "__index__") && !py::isinstance<py::str>(value)));
}

} // namespace

std::string typeName(py::handle value) {
    if (value.is_none()) return "None";
    std::string name = py::str(value.get_type().attr("__name__")).cast<std::string>();
    // A short value says more than the type alone: "str 'fog'", "int 5".
    if (py::isinstance<py::str>(value) || PyLong_Check(value.ptr()) || PyFloat_Check(value.ptr())) {
        const std::string r = py::repr(value).cast<std::string>();
        if (r.size() <= 40) name += " " + r;
    }
    return name;
}

long long toInt(py::handle value, const std::string& name) {
    if (!isIntLike(value)) wrongType(value, name, "an int");
    py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr()));
    if (!index) {
        PyErr_Clear();
        wrongType(value, name, "an int");
    }
    const long long v = PyLong_AsLongLong(index.ptr());
    if (v == -1 && PyErr_Occurred()) {
        PyErr_Clear();
        throw PyError(ErrorKind::Value,
                      fmt::format("{}: {} does not fit in 64 bits", name,
                                  printable(py::str(index).cast<std::string>(), 60)));
    }
    return v;
}

std::optional<long long> toOptInt(py::handle value, const std::string& name) {
    if (value.is_none()) return std::nullopt;
    if (!isIntLike(value)) wrongType(value, name, "an int or None");
    return toInt(value, name);
}

double toFloat(py::handle value, const std::string& name) {
    const bool number = !isBool(value) && !py::isinstance<py::str>(value) &&
                        (PyFloat_Check(value.ptr()) || PyLong_Check(value.ptr()) ||
                         py::hasattr(value, "__float__"));
    if (!number) wrongType(value, name, "a number (int or float)");
    const double v = PyFloat_AsDouble(value.ptr());
    if (v == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        throw PyError(ErrorKind::Value, fmt::format("{}: {} is not a float", name,
                                                    py::repr(value).cast<std::string>()));
    }
    return v;
}

bool toBool(py::handle value, const std::string& name) {
    if (isBool(value)) return value.ptr() == Py_True;
    if (py::hasattr(value, "dtype") && py::str(value.attr("dtype")).cast<std::string>() == "bool")
        return value.attr("__bool__")().cast<bool>();
    wrongType(value, name, "a bool (True or False)");
}

std::string toStr(py::handle value, const std::string& name) {
    if (!py::isinstance<py::str>(value)) wrongType(value, name, "a str");
    return value.cast<std::string>();
}

std::optional<std::string> toOptStr(py::handle value, const std::string& name) {
    if (value.is_none()) return std::nullopt;
    if (!py::isinstance<py::str>(value)) wrongType(value, name, "a str or None");
    return value.cast<std::string>();
}

std::vector<std::string> toStrList(py::handle value, const std::string& name, bool single) {
    if (single && py::isinstance<py::str>(value)) return {value.cast<std::string>()};
    const char* expected = single ? "a str or a list of str" : "a list of str";
    if (!py::isinstance<py::list>(value) && !py::isinstance<py::tuple>(value))
        wrongType(value, name, expected);
    std::vector<std::string> out;
    std::size_t i = 0;
    for (py::handle item : value) {
        if (!py::isinstance<py::str>(item))
            throw PyError(ErrorKind::Type,
                          fmt::format("{}[{}]: expected a str, got {}", name, i, typeName(item)));
        out.push_back(item.cast<std::string>());
        ++i;
    }
    return out;
}

std::vector<int> toIntList(py::handle value, const std::string& name) {
    if (!py::isinstance<py::list>(value) && !py::isinstance<py::tuple>(value) &&
        !(py::hasattr(value, "tolist") && py::hasattr(value, "dtype")))
        wrongType(value, name, "a list of int");
    py::object items = py::reinterpret_borrow<py::object>(value);
    if (py::hasattr(value, "tolist")) items = value.attr("tolist")();
    std::vector<int> out;
    std::size_t i = 0;
    for (py::handle item : items) {
        const std::string at = fmt::format("{}[{}]", name, i++);
        const long long v = toInt(item, at);
        VEIL_PY_CHECK(ErrorKind::Value, v >= INT32_MIN && v <= INT32_MAX,
                      "{}: {} does not fit in 32 bits", at, v);
        out.push_back(static_cast<int>(v));
    }
    return out;
}

} // namespace veil::python
