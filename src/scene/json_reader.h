// Reading the JSON scene format (docs/scene-format.md): the file and JSON pointer carried into
// every message (Context, fail, at), numbers checked for range and for fitting a float, and
// objects whose accepted keys are declared when they are opened (Obj), so a misspelt key is
// reported with the keys that would have been accepted. Used by scene_json.cpp only.
#pragma once

#include "base/error.h"
#include "base/suggest.h"
#include "scene/json_text.h"

#include <nlohmann/json.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <system_error>
#include <vector>

namespace veil::scene::detail {

using nlohmann::json;
namespace fs = std::filesystem;

inline constexpr double kInf = std::numeric_limits<double>::infinity();

struct Context {
    std::string source; // file name for messages
    fs::path baseDir;
};

[[noreturn]] inline void fail(const Context& ctx, const std::string& ptr,
                              const std::string& problem) {
    throw Error(fmt::format("{}: {}: {}", ctx.source, ptr.empty() ? "/" : ptr, problem));
}

// Runs f and prefixes any veil::Error it throws with the file and pointer.
template <typename F>
auto at(const Context& ctx, const std::string& ptr, F&& f) {
    try {
        return f();
    } catch (const Error& e) {
        fail(ctx, ptr, e.what());
    }
}

inline std::string child(const std::string& ptr, const std::string& key) {
    std::string escaped; // RFC 6901
    for (char c : key)
        escaped += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
    return ptr + "/" + escaped;
}
inline std::string child(const std::string& ptr, std::size_t index) {
    return ptr + "/" + std::to_string(index);
}

// Bounded: a value may be megabytes or thousands of levels deep (json_text.h).
inline std::string show(const json& v) { return describeJson(v, 60); }

inline std::string joined(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names)
        out += (out.empty() ? "" : ", ") + n;
    return out;
}

// Numeric range; open ends exclude the bound.
struct Range {
    double lo = -kInf, hi = kInf;
    bool loOpen = false, hiOpen = false;
    bool contains(double v) const {
        return (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi);
    }
    std::string str() const {
        return fmt::format("{}{}, {}{}", loOpen ? '(' : '[', lo, hi, hiOpen ? ')' : ']');
    }
};
inline const Range kAny{};
inline const Range kUnit{0.0, 1.0};
inline const Range kNonNegative{0.0, kInf};
inline const Range kPositive{0.0, kInf, true};

inline double number(const Context& ctx, const json& v, const std::string& ptr, Range r) {
    if (!v.is_number()) fail(ctx, ptr, fmt::format("expected a number, got {}", show(v)));
    double d = v.get<double>();
    if (!std::isfinite(d)) fail(ctx, ptr, fmt::format("value {} is not a finite number", d));
    // Every number read here is stored as a float: 1e39 would become inf, 1e-50 zero.
    if (std::abs(d) > std::numeric_limits<float>::max() || (d != 0.0 && float(d) == 0.0f))
        fail(ctx, ptr, fmt::format("value {} does not fit a 32-bit float", show(v)));
    if (!r.contains(d)) fail(ctx, ptr, fmt::format("value {} out of range {}", show(v), r.str()));
    return d;
}

inline long long integer(const Context& ctx, const json& v, const std::string& ptr, long long lo,
                         long long hi) {
    bool integral =
        v.is_number_integer() || (v.is_number_float() && std::isfinite(v.get<double>()) &&
                                  std::floor(v.get<double>()) == v.get<double>());
    if (!integral) fail(ctx, ptr, fmt::format("expected an integer, got {}", show(v)));
    double d = v.get<double>(); // exact enough for the ranges used here (at most 2^32)
    if (d < double(lo) || d > double(hi))
        fail(ctx, ptr, fmt::format("value {} out of range [{}, {}]", show(v), lo, hi));
    return v.is_number_integer() ? v.get<long long>() : (long long)d;
}

template <int N>
glm::vec<N, float> vec(const Context& ctx, const json& v, const std::string& ptr, Range r,
                       bool allowScalar) {
    if (allowScalar && v.is_number()) return glm::vec<N, float>(float(number(ctx, v, ptr, r)));
    if (!v.is_array() || v.size() != N)
        fail(ctx, ptr,
             fmt::format("expected an array of {} numbers{}, got {}", N,
                         allowScalar ? " or a number" : "", show(v)));
    glm::vec<N, float> out;
    for (int i = 0; i < N; ++i)
        out[i] = float(number(ctx, v[i], child(ptr, i), r));
    return out;
}

// A JSON object whose accepted keys are declared when it is opened.
class Obj {
public:
    Obj(const Context& ctx, const json& j, std::string ptr, std::vector<std::string> known)
        : ctx_(ctx), j_(j), ptr_(std::move(ptr)), known_(std::move(known)) {
        if (!j_.is_object()) fail(ctx_, ptr_, fmt::format("expected an object, got {}", show(j_)));
        for (const auto& item : j_.items()) {
            if (std::find(known_.begin(), known_.end(), item.key()) == known_.end())
                fail(ctx_, child(ptr_, item.key()),
                     fmt::format("unknown key{} (known: {})", didYouMean(item.key(), known_),
                                 joined(known_)));
        }
    }

    const Context& ctx() const { return ctx_; }
    const std::string& ptr() const { return ptr_; }
    std::string ptr(const std::string& key) const { return child(ptr_, key); }
    const json* get(const std::string& key) const {
        auto it = j_.find(key);
        return it == j_.end() ? nullptr : &*it;
    }
    bool has(const std::string& key) const { return get(key) != nullptr; }
    const json& require(const std::string& key) const {
        const json* v = get(key);
        if (!v) fail(ctx_, ptr_, fmt::format("missing required key '{}'", key));
        return *v;
    }

    float num(const std::string& key, float def, Range r = kAny) const {
        const json* v = get(key);
        return v ? float(number(ctx_, *v, ptr(key), r)) : def;
    }
    long long integer(const std::string& key, long long def, long long lo, long long hi) const {
        const json* v = get(key);
        return v ? detail::integer(ctx_, *v, ptr(key), lo, hi) : def;
    }
    bool boolean(const std::string& key, bool def) const {
        const json* v = get(key);
        if (!v) return def;
        if (!v->is_boolean())
            fail(ctx_, ptr(key), fmt::format("expected true or false, got {}", show(*v)));
        return v->get<bool>();
    }
    std::string str(const std::string& key, const std::string& def,
                    const std::vector<std::string>& allowed = {}) const {
        const json* v = get(key);
        if (!v) return def;
        if (!v->is_string())
            fail(ctx_, ptr(key), fmt::format("expected a string, got {}", show(*v)));
        std::string s = v->get<std::string>();
        if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), s) == allowed.end())
            fail(ctx_, ptr(key),
                 fmt::format("unknown value '{}' (allowed: {})", s, joined(allowed)));
        return s;
    }
    template <int N>
    glm::vec<N, float> vec(const std::string& key, glm::vec<N, float> def, Range r = kAny,
                           bool allowScalar = false) const {
        const json* v = get(key);
        return v ? detail::vec<N>(ctx_, *v, ptr(key), r, allowScalar) : def;
    }
    // Colors: non-negative RGB, a single number meaning grey.
    glm::vec3 color(const std::string& key, glm::vec3 def, Range r = kNonNegative) const {
        return vec<3>(key, def, r, true);
    }

private:
    const Context& ctx_;
    const json& j_;
    std::string ptr_;
    std::vector<std::string> known_;
};

// Iterates a JSON array at `key` (absent = empty) as (element, pointer) pairs.
template <typename F>
void forEach(const Obj& parent, const std::string& key, F&& f) {
    const json* arr = parent.get(key);
    if (!arr) return;
    if (!arr->is_array())
        fail(parent.ctx(), parent.ptr(key), fmt::format("expected an array, got {}", show(*arr)));
    for (std::size_t i = 0; i < arr->size(); ++i)
        f((*arr)[i], child(parent.ptr(key), i), i);
}

inline fs::path resolvePath(const Obj& o, const std::string& key, const char* what) {
    std::string s = o.str(key, "");
    if (s.empty()) fail(o.ctx(), o.ptr(key), fmt::format("{} path must not be empty", what));
    fs::path p(s);
    if (p.is_relative()) p = o.ctx().baseDir / p;
    p = p.lexically_normal();
    std::error_code ec;
    if (!fs::exists(p, ec))
        fail(o.ctx(), o.ptr(key), fmt::format("{} '{}' does not exist", what, p.string()));
    if (!fs::is_regular_file(p, ec))
        fail(
            o.ctx(), o.ptr(key),
            fmt::format("{} '{}' is not a regular file (a directory or device)", what, p.string()));
    return p;
}

} // namespace veil::scene::detail
