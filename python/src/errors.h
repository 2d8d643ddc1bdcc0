// The module's exception classes and the one place where C++ errors become them.
//
// veil.Error (a RuntimeError) is the base; each class below is also the standard exception a
// Python caller expects (veil.FileNotFoundError is a FileNotFoundError, ...). The bindings
// throw PyError with a kind where they know it (argument checks); a veil::Error of the
// libraries is classified by its message (classifyMessage), a std::filesystem error by its
// code, std::bad_alloc is a MemoryError.
#pragma once

#include "base/error.h"

#include <fmt/format.h>
#include <pybind11/pybind11.h>

#include <string>

namespace veil::python {

namespace py = pybind11;

enum class ErrorKind {
    Error,        // veil.Error: GL, rendering, anything not classified below
    Value,        // veil.ValueError: a bad value (scene content, a number out of range)
    Key,          // veil.KeyError: an unknown key or name (also a ValueError)
    Type,         // veil.TypeError: an argument of the wrong type
    FileNotFound, // veil.FileNotFoundError: an input file or folder that does not exist
    OS,           // veil.OSError: any other file-system failure
    Memory,       // veil.MemoryError
};

class PyError : public Error {
public:
    PyError(ErrorKind kind, const std::string& message, std::string filename = {})
        : Error(message), kind_(kind), filename_(std::move(filename)) {}
    ErrorKind kind() const { return kind_; }
    const std::string& filename() const { return filename_; }

private:
    ErrorKind kind_;
    std::string filename_;
};

// VEIL_PY_CHECK(ErrorKind::Value, cond, "fmt {}", args...) throws PyError of that kind.
#define VEIL_PY_CHECK(kind, cond, ...)                                                             \
    do {                                                                                           \
        if (!(cond)) throw ::veil::python::PyError(kind, fmt::format(__VA_ARGS__));                \
    } while (0)

// The kind of a library error by its message: missing files, unknown keys, out of memory;
// `fallback` for the rest (ErrorKind::Value while checking input, Error while rendering).
ErrorKind classifyMessage(const std::string& message, ErrorKind fallback);

// Runs f; a veil::Error that is not yet a PyError leaves as one, classified with `fallback`.
template <class F>
auto classified(ErrorKind fallback, F&& f) {
    try {
        return f();
    } catch (const PyError&) {
        throw;
    } catch (const Error& e) {
        throw PyError(classifyMessage(e.what(), fallback), e.what());
    }
}

// Creates veil.Error and its subclasses in `m` and registers the translator.
void registerErrors(py::module_& m);

// The Python class of a kind (for the Python part: veil.testing raises them too).
py::handle errorClass(ErrorKind kind);

} // namespace veil::python
