#include "base/properties.h"

#include "base/error.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace veil {

using nlohmann::json;

namespace {

std::string joined(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names)
        out += (out.empty() ? "" : ", ") + n;
    return out;
}

// A short, bounded description of a JSON value for messages (never dumps a deep document).
std::string brief(const json& v) {
    switch (v.type()) {
    case json::value_t::object:
        return fmt::format("an object of {} keys", v.size());
    case json::value_t::array:
        return fmt::format("an array of {} elements", v.size());
    case json::value_t::string: {
        const auto& s = v.get_ref<const std::string&>();
        std::string shown;
        for (char c : s.substr(0, 40))
            shown += (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e)
                         ? '?'
                         : c;
        return fmt::format("\"{}{}\"", shown, s.size() > 40 ? "..." : "");
    }
    case json::value_t::number_float:
        return fmt::format("{}", v.get<double>());
    case json::value_t::number_integer:
        return fmt::format("{}", v.get<long long>());
    case json::value_t::number_unsigned:
        return fmt::format("{}", v.get<unsigned long long>());
    case json::value_t::boolean:
        return v.get<bool>() ? "true" : "false";
    case json::value_t::null:
        return "null";
    default:
        return v.type_name();
    }
}

std::string fmtNumber(double d) {
    if (d == std::numeric_limits<double>::infinity()) return "inf";
    if (d == -std::numeric_limits<double>::infinity()) return "-inf";
    return fmt::format("{}", d);
}

double checkedNumber(const PropertyDecl& d, const json& v, const std::string& path) {
    if (!v.is_number()) throw Error(fmt::format("{}: expected a number, got {}", path, brief(v)));
    const double x = v.get<double>();
    if (!std::isfinite(x) || std::fabs(x) > double(FLT_MAX))
        throw Error(fmt::format("{}: {} does not fit a finite 32-bit float", path, brief(v)));
    if (x < d.min || x > d.max)
        throw Error(fmt::format("{}: value {} out of range {}", path, brief(v), d.rangeText()));
    return x;
}

json checkValue(const PropertyDecl& d, const json& v, const std::string& path) {
    switch (d.type) {
    case PropertyType::Bool:
        if (!v.is_boolean())
            throw Error(fmt::format("{}: expected true or false, got {}", path, brief(v)));
        return v;
    case PropertyType::Int: {
        const bool integral =
            v.is_number_integer() || (v.is_number_float() && std::isfinite(v.get<double>()) &&
                                      std::floor(v.get<double>()) == v.get<double>());
        if (!integral) throw Error(fmt::format("{}: expected an integer, got {}", path, brief(v)));
        const double x = v.get<double>();
        if (x < d.min || x > d.max)
            throw Error(fmt::format("{}: value {} out of range {}", path, brief(v), d.rangeText()));
        return json(static_cast<long long>(x));
    }
    case PropertyType::Float:
        return json(checkedNumber(d, v, path));
    case PropertyType::Vec3:
    case PropertyType::Color: {
        if (!v.is_array() || v.size() != 3)
            throw Error(fmt::format("{}: expected an array of 3 numbers, got {}", path, brief(v)));
        json out = json::array();
        for (std::size_t i = 0; i < 3; ++i)
            out.push_back(checkedNumber(d, v[i], fmt::format("{}/{}", path, i)));
        return out;
    }
    case PropertyType::Enum: {
        if (!v.is_string())
            throw Error(fmt::format("{}: expected a string, got {}", path, brief(v)));
        const auto& s = v.get_ref<const std::string&>();
        if (std::find(d.choices.begin(), d.choices.end(), s) == d.choices.end())
            throw Error(fmt::format("{}: {} is not one of {}", path, brief(v), joined(d.choices)));
        return v;
    }
    case PropertyType::String:
        if (!v.is_string())
            throw Error(fmt::format("{}: expected a string, got {}", path, brief(v)));
        return v;
    }
    throw Error(fmt::format("{}: unhandled property type", path));
}

} // namespace

const char* propertyTypeName(PropertyType type) {
    switch (type) {
    case PropertyType::Bool:
        return "bool";
    case PropertyType::Int:
        return "int";
    case PropertyType::Float:
        return "float";
    case PropertyType::Vec3:
        return "vec3";
    case PropertyType::Color:
        return "color";
    case PropertyType::Enum:
        return "enum";
    case PropertyType::String:
        return "string";
    }
    return "?";
}

std::string PropertyDecl::rangeText() const {
    switch (type) {
    case PropertyType::Enum:
        return fmt::format("{{{}}}", joined(choices));
    case PropertyType::Bool:
    case PropertyType::String:
        return {};
    default:
        if (std::isinf(min) && std::isinf(max)) return {};
        return fmt::format("[{}, {}]", fmtNumber(min), fmtNumber(max));
    }
}

PropertySchema& PropertySchema::add(PropertyDecl decl) {
    VEIL_CHECK(!find(decl.key), "property '{}' declared twice", decl.key);
    // The default must satisfy the declaration itself.
    decl.defaultValue = checkValue(decl, decl.defaultValue, "default of " + decl.key);
    decls_.push_back(std::move(decl));
    return *this;
}

PropertySchema& PropertySchema::boolean(std::string key, bool def, std::string doc,
                                        std::string citation) {
    return add(
        {std::move(key), PropertyType::Bool, def, 0, 1, {}, std::move(doc), std::move(citation)});
}
PropertySchema& PropertySchema::integer(std::string key, long long def, long long min,
                                        long long max, std::string doc, std::string citation) {
    return add({std::move(key),
                PropertyType::Int,
                def,
                double(min),
                double(max),
                {},
                std::move(doc),
                std::move(citation)});
}
PropertySchema& PropertySchema::real(std::string key, double def, double min, double max,
                                     std::string doc, std::string citation) {
    return add({std::move(key),
                PropertyType::Float,
                def,
                min,
                max,
                {},
                std::move(doc),
                std::move(citation)});
}
PropertySchema& PropertySchema::vec3(std::string key, glm::vec3 def, double min, double max,
                                     std::string doc, std::string citation) {
    return add({std::move(key),
                PropertyType::Vec3,
                json::array({def.x, def.y, def.z}),
                min,
                max,
                {},
                std::move(doc),
                std::move(citation)});
}
PropertySchema& PropertySchema::color(std::string key, glm::vec3 def, std::string doc,
                                      std::string citation) {
    return add({std::move(key),
                PropertyType::Color,
                json::array({def.x, def.y, def.z}),
                0.0,
                std::numeric_limits<double>::infinity(),
                {},
                std::move(doc),
                std::move(citation)});
}
PropertySchema& PropertySchema::choice(std::string key, std::string def,
                                       std::vector<std::string> choices, std::string doc,
                                       std::string citation) {
    return add({std::move(key), PropertyType::Enum, std::move(def), 0, 0, std::move(choices),
                std::move(doc), std::move(citation)});
}
PropertySchema& PropertySchema::text(std::string key, std::string def, std::string doc,
                                     std::string citation) {
    return add({std::move(key),
                PropertyType::String,
                std::move(def),
                0,
                0,
                {},
                std::move(doc),
                std::move(citation)});
}

PropertySchema& PropertySchema::withDefault(const std::string& key, json value) {
    auto it = std::find_if(decls_.begin(), decls_.end(),
                           [&](const PropertyDecl& d) { return d.key == key; });
    VEIL_CHECK(it != decls_.end(), "withDefault: property '{}' is not declared", key);
    it->defaultValue = checkValue(*it, value, "default of " + key);
    return *this;
}

const PropertyDecl* PropertySchema::find(const std::string& key) const {
    for (const PropertyDecl& d : decls_)
        if (d.key == key) return &d;
    return nullptr;
}

std::vector<std::string> PropertySchema::keys() const {
    std::vector<std::string> k;
    for (const PropertyDecl& d : decls_)
        k.push_back(d.key);
    return k;
}

Properties PropertySchema::defaults() const { return resolve(json(), "<defaults>"); }

Properties PropertySchema::resolve(const json& values, const std::string& where,
                                   const std::string& owner,
                                   const std::vector<std::string>& ignore) const {
    Properties p;
    p.decls_ = decls_;
    for (const PropertyDecl& d : decls_)
        p.values_[d.key] = d.defaultValue;
    if (values.is_null()) return p;
    if (!values.is_object())
        throw Error(
            fmt::format("{}: expected an object of properties, got {}", where, brief(values)));
    for (const auto& item : values.items()) {
        const std::string& key = item.key();
        if (std::find(ignore.begin(), ignore.end(), key) != ignore.end()) continue;
        const std::string path = where + "/" + key;
        const PropertyDecl* d = find(key);
        if (!d)
            throw Error(fmt::format("{}: unknown key{} (accepted: {})", path,
                                    owner.empty() ? "" : " of " + owner,
                                    decls_.empty() ? std::string("none") : joined(keys())));
        p.values_[key] = checkValue(*d, item.value(), path);
    }
    return p;
}

json PropertySchema::describe() const {
    json out = json::array();
    for (const PropertyDecl& d : decls_)
        out.push_back({{"key", d.key},
                       {"type", propertyTypeName(d.type)},
                       {"default", d.defaultValue},
                       {"range", d.rangeText()},
                       {"doc", d.doc},
                       {"citation", d.citation}});
    return out;
}

const json& Properties::at(const std::string& key, PropertyType type) const {
    for (const PropertyDecl& d : decls_) {
        if (d.key != key) continue;
        const bool ok = d.type == type ||
                        (type == PropertyType::Vec3 && d.type == PropertyType::Color) ||
                        (type == PropertyType::String && d.type == PropertyType::Enum) ||
                        (type == PropertyType::Float && d.type == PropertyType::Int);
        VEIL_CHECK(ok, "property '{}' is a {}, read as {}", key, propertyTypeName(d.type),
                   propertyTypeName(type));
        return values_.at(key);
    }
    throw Error(fmt::format("property '{}' is not declared", key));
}

bool Properties::getBool(const std::string& key) const {
    return at(key, PropertyType::Bool).get<bool>();
}
int Properties::getInt(const std::string& key) const {
    return static_cast<int>(at(key, PropertyType::Int).get<long long>());
}
float Properties::getFloat(const std::string& key) const {
    return static_cast<float>(at(key, PropertyType::Float).get<double>());
}
double Properties::getDouble(const std::string& key) const {
    return at(key, PropertyType::Float).get<double>();
}
glm::vec3 Properties::getVec3(const std::string& key) const {
    const json& v = at(key, PropertyType::Vec3);
    return {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()};
}
std::string Properties::getString(const std::string& key) const {
    return at(key, PropertyType::String).get<std::string>();
}

Properties& Properties::set(const std::string& key, const json& value) {
    for (const PropertyDecl& d : decls_)
        if (d.key == key) {
            values_[key] = checkValue(d, value, key);
            return *this;
        }
    throw Error(fmt::format("{}: unknown key (accepted: {})", key, [&] {
        std::vector<std::string> k;
        for (const PropertyDecl& d : decls_)
            k.push_back(d.key);
        return joined(k);
    }()));
}

} // namespace veil
