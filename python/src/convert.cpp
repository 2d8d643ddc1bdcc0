#include "convert.h"

#include "base/error.h"
#include "base/text.h"
#include "scene/json_text.h"

#include <fmt/format.h>

#include <cmath>

namespace veil::python {

py::object toPython(const nlohmann::json& value) {
    switch (value.type()) {
    case nlohmann::json::value_t::null:
        return py::none();
    case nlohmann::json::value_t::boolean:
        return py::bool_(value.get<bool>());
    case nlohmann::json::value_t::number_integer:
        return py::int_(value.get<long long>());
    case nlohmann::json::value_t::number_unsigned:
        return py::int_(value.get<unsigned long long>());
    case nlohmann::json::value_t::number_float:
        return py::float_(value.get<double>());
    case nlohmann::json::value_t::string:
        return py::str(value.get<std::string>());
    case nlohmann::json::value_t::array: {
        py::list out;
        for (const auto& v : value)
            out.append(toPython(v));
        return out;
    }
    case nlohmann::json::value_t::object: {
        py::dict out;
        for (const auto& [k, v] : value.items())
            out[py::str(k)] = toPython(v);
        return out;
    }
    default:
        return py::none();
    }
}

namespace {

nlohmann::json fromPythonAt(py::handle value, const std::string& what, const std::string& where,
                            std::size_t depth) {
    const auto at = [&] { return what + ": " + (where.empty() ? "/" : printable(where, 120)); };
    if (value.is_none()) return nullptr;
    if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
    if (py::isinstance<py::int_>(value)) {
        try {
            return value.cast<long long>();
        } catch (const py::cast_error&) {
            throw PyError(ErrorKind::Value,
                          fmt::format("{}: integer {} does not fit in 64 bits", at(),
                                      printable(py::str(value).cast<std::string>(), 60)));
        }
    }
    if (py::isinstance<py::float_>(value)) {
        const double d = value.cast<double>();
        VEIL_PY_CHECK(ErrorKind::Value, std::isfinite(d),
                      "{}: {} is not a finite number (JSON has no NaN or inf)", at(), d);
        return d;
    }
    if (py::isinstance<py::str>(value)) return value.cast<std::string>();
    const bool dict = py::isinstance<py::dict>(value);
    if (dict || py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
        // The cap comes before the recursion: a 200000-deep list (or a list holding itself)
        // would otherwise overflow the stack here or in nlohmann later.
        VEIL_PY_CHECK(ErrorKind::Value, depth < scene::kMaxJsonDepth,
                      "{}: nested deeper than {} levels (the limit of a scene document)", at(),
                      scene::kMaxJsonDepth);
    }
    if (dict) {
        nlohmann::json out = nlohmann::json::object();
        for (auto item : value.cast<py::dict>()) {
            VEIL_PY_CHECK(ErrorKind::Type, py::isinstance<py::str>(item.first),
                          "{}: key {} is not a str", at(),
                          printable(py::repr(item.first).cast<std::string>(), 60));
            const std::string key = item.first.cast<std::string>();
            out[key] = fromPythonAt(item.second, what, where + "/" + key, depth + 1);
        }
        return out;
    }
    if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
        nlohmann::json out = nlohmann::json::array();
        std::size_t i = 0;
        for (auto item : value)
            out.push_back(fromPythonAt(item, what, where + "/" + std::to_string(i++), depth + 1));
        return out;
    }
    // NumPy scalars and arrays: through their Python equivalents (an array's tolist() nests
    // one list per dimension, counted as the lists are).
    if (py::hasattr(value, "tolist") && py::hasattr(value, "dtype"))
        return fromPythonAt(value.attr("tolist")(), what, where, depth);
    throw PyError(ErrorKind::Type,
                  fmt::format("{}: a value of type {} is not JSON (use dict, list, str, int, "
                              "float, bool or None)",
                              at(),
                              py::str(value.get_type().attr("__name__")).cast<std::string>()));
}

} // namespace

nlohmann::json fromPython(py::handle value, const std::string& what) {
    return fromPythonAt(value, what, "", 0);
}

py::array_t<float> toArray(ImageF image, bool squeeze) {
    auto* owned = new ImageF(std::move(image));
    py::capsule owner(owned, [](void* p) { delete static_cast<ImageF*>(p); });
    const py::ssize_t h = owned->height, w = owned->width, c = owned->channels;
    if (squeeze && c == 1)
        return py::array_t<float>({h, w},
                                  {w * py::ssize_t(sizeof(float)), py::ssize_t(sizeof(float))},
                                  owned->pixels.data(), owner);
    return py::array_t<float>({h, w, c},
                              {w * c * py::ssize_t(sizeof(float)), c * py::ssize_t(sizeof(float)),
                               py::ssize_t(sizeof(float))},
                              owned->pixels.data(), owner);
}

py::array_t<float> channelView(const py::array_t<float>& whole, int first, int channels) {
    const py::ssize_t h = whole.shape(0), w = whole.shape(1);
    const float* base = whole.data() + first;
    if (channels == 1)
        return py::array_t<float>({h, w}, {whole.strides(0), whole.strides(1)}, base, whole);
    return py::array_t<float>({h, w, py::ssize_t(channels)},
                              {whole.strides(0), whole.strides(1), whole.strides(2)}, base, whole);
}

ImageF fromArray(py::handle value, const std::string& what) {
    py::array_t<float, py::array::c_style | py::array::forcecast> a;
    try {
        a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
    } catch (const py::error_already_set&) {
    }
    VEIL_PY_CHECK(a ? ErrorKind::Value : ErrorKind::Type,
                  a && a.ndim() >= 2 && a.ndim() <= 3 &&
                      (a.ndim() == 2 || (a.shape(2) >= 1 && a.shape(2) <= 4)),
                  "{}: expected an image array of shape HxW or HxWxC (C = 1 to 4) of numbers, "
                  "got {}",
                  what, printable(py::repr(value).cast<std::string>(), 120));
    const int h = static_cast<int>(a.shape(0)), w = static_cast<int>(a.shape(1));
    const int c = a.ndim() == 2 ? 1 : static_cast<int>(a.shape(2));
    VEIL_PY_CHECK(ErrorKind::Value, h > 0 && w > 0, "{}: the image is empty ({}x{})", what, w, h);
    ImageF out(w, h, c);
    std::copy(a.data(), a.data() + out.pixels.size(), out.pixels.begin());
    return out;
}

bool isPathLike(py::handle value) {
    return py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__");
}

std::filesystem::path toPath(py::handle value, const std::string& what) {
    VEIL_PY_CHECK(ErrorKind::Type, isPathLike(value),
                  "{}: expected a path (str or os.PathLike), got {}", what, typeName(value));
    py::object text = py::module_::import("os").attr("fspath")(value);
    VEIL_PY_CHECK(ErrorKind::Type, py::isinstance<py::str>(text),
                  "{}: expected a str path, not bytes", what);
    return std::filesystem::path(text.cast<std::string>());
}

} // namespace veil::python
