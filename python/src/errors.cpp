#include "errors.h"

#include <nlohmann/json.hpp>
#include <pybind11/eval.h>

#include <filesystem>
#include <new>
#include <stdexcept>

namespace veil::python {

namespace {

// The classes, made in Python so that each is also its standard class and prints the one
// line it carries (str(KeyError) would quote it, str(OSError) with a filename would not be
// the message). Their __module__ is "veil", so tracebacks name veil.FileNotFoundError.
constexpr const char* kClasses = R"py(
import builtins as _b

class Error(_b.RuntimeError):
    """What failed, in the one line `veil` prints (veil: error: ...). The base of the classes
    below, each of which is also the standard exception of its kind."""
    __module__ = "veil"

    def __str__(self):
        return str(self.args[0]) if self.args else ""

class ValueError(Error, _b.ValueError):
    """A bad value: scene content, a number out of range, an unknown technique or metric."""
    __module__ = "veil"

class KeyError(Error, _b.KeyError, _b.ValueError):
    """An unknown key of a scene or property (also a ValueError)."""
    __module__ = "veil"
    __str__ = Error.__str__

class TypeError(Error, _b.TypeError):
    """An argument of the wrong type; the message names the argument and what it accepts."""
    __module__ = "veil"

class FileNotFoundError(Error, _b.FileNotFoundError):
    """An input file or folder that does not exist (filename: the path when known)."""
    __module__ = "veil"
    __str__ = Error.__str__

class OSError(Error, _b.OSError):
    """Any other file-system failure (filename: the path when known)."""
    __module__ = "veil"
    __str__ = Error.__str__

class MemoryError(Error, _b.MemoryError):
    """Memory ran out (the message says for what when known)."""
    __module__ = "veil"
)py";

constexpr const char* kNames[] = {
    "Error", "ValueError", "KeyError", "TypeError", "FileNotFoundError", "OSError", "MemoryError"};

py::handle classes[std::size(kNames)];

bool contains(const std::string& text, const char* part) {
    return text.find(part) != std::string::npos;
}

void raise(ErrorKind kind, const std::string& message, const std::string& filename = {}) {
    py::gil_scoped_acquire gil;
    py::handle cls = errorClass(kind);
    try {
        py::object value = cls(message);
        if (!filename.empty() && (kind == ErrorKind::FileNotFound || kind == ErrorKind::OS))
            value.attr("filename") = filename;
        PyErr_SetObject(cls.ptr(), value.ptr());
    } catch (py::error_already_set& e) {
        e.restore();
    }
}

} // namespace

ErrorKind classifyMessage(const std::string& m, ErrorKind fallback) {
    if (contains(m, "out of memory")) return ErrorKind::Memory;
    if (contains(m, ": no such file") || (contains(m, "does not exist") && !contains(m, "glTF")))
        return ErrorKind::FileNotFound;
    if (contains(m, "unknown key")) return ErrorKind::Key;
    return fallback;
}

py::handle errorClass(ErrorKind kind) { return classes[static_cast<std::size_t>(kind)]; }

void registerErrors(py::module_& m) {
    py::dict scope;
    py::exec(kClasses, scope);
    for (std::size_t i = 0; i < std::size(kNames); ++i) {
        py::object cls = scope[kNames[i]];
        m.attr(kNames[i]) = cls;
        classes[i] = cls.release(); // kept for the life of the process, as the module's
    }
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const PyError& e) {
            raise(e.kind(), e.what(), e.filename());
        } catch (const Error& e) {
            raise(classifyMessage(e.what(), ErrorKind::Error), e.what());
        } catch (const nlohmann::json::exception& e) {
            raise(ErrorKind::Value, e.what());
        } catch (const std::filesystem::filesystem_error& e) {
            const std::string path = e.path1().string();
            const bool missing = e.code() == std::errc::no_such_file_or_directory;
            std::string message = path.empty() ? std::string() : "'" + path + "': ";
            message += e.code().message();
            if (!e.path2().empty()) message += " (with '" + e.path2().string() + "')";
            raise(missing ? ErrorKind::FileNotFound : ErrorKind::OS, message, path);
        } catch (const std::bad_alloc&) {
            raise(ErrorKind::Memory, "out of memory (the request needs more memory than the "
                                     "machine gives; try a smaller size)");
        } catch (const std::length_error& e) {
            raise(ErrorKind::Memory,
                  std::string("out of memory (a size too large: ") + e.what() + ")");
        } catch (const py::cast_error& e) {
            raise(ErrorKind::Type, e.what());
        }
    });
    // The C++ exceptions of the libraries that are not veil::Error, thrown on demand so that
    // the tests see how each reaches Python.
    m.def("_raise_cpp", [](const std::string& what) {
        namespace fs = std::filesystem;
        if (what == "bad_alloc") throw std::bad_alloc();
        if (what == "length_error") throw std::length_error("vector::reserve");
        if (what == "no_such_file")
            throw fs::filesystem_error("status", fs::path("/nonexistent/x.exr"),
                                       std::make_error_code(std::errc::no_such_file_or_directory));
        if (what == "permission")
            throw fs::filesystem_error("create_directory", fs::path("/proc/x"),
                                       std::make_error_code(std::errc::permission_denied));
        throw Error("_raise_cpp: unknown '" + what + "'");
    });
}

} // namespace veil::python
