// Typed technique and pass parameters, declared once (docs/architecture.md "One frame: passes and
// resources"; the model is Falcor's property maps and Mitsuba's Properties, where a key nobody
// reads is an error).
//
// A PropertySchema lists what a technique accepts: key, type, default, valid range or
// choices, a one-line doc and the paper equation the parameter comes from. The same
// declaration drives the scene file (`"render": {"oit": {"type": "moment-p6", "bias": 5e-6}}`),
// `--set render.oit.bias=5e-6`, `veil techniques`, the `--report` JSON (effective values) and
// the viewer's widgets. PropertySchema::resolve() validates a JSON object against it and
// returns the effective values: an unknown key or a value of the wrong type or out of range
// throws veil::Error naming the JSON path and listing the accepted keys.
#pragma once

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <limits>
#include <string>
#include <vector>

namespace veil {

enum class PropertyType { Bool, Int, Float, Vec3, Color, Enum, String };
const char* propertyTypeName(PropertyType type);

struct PropertyDecl {
    std::string key;
    PropertyType type = PropertyType::Float;
    nlohmann::json defaultValue;
    double min = -std::numeric_limits<double>::infinity(); // numbers and vector components
    double max = std::numeric_limits<double>::infinity();
    std::vector<std::string> choices; // Enum
    std::string doc;                  // one line
    std::string citation;             // paper equation, e.g. "[Munstermann18 sec. 3.2]"

    // "[0, 1]", "{a, b}" or "" for unbounded numbers and strings.
    std::string rangeText() const;
};

class Properties;

class PropertySchema {
public:
    PropertySchema& boolean(std::string key, bool def, std::string doc, std::string citation = {});
    PropertySchema& integer(std::string key, long long def, long long min, long long max,
                            std::string doc, std::string citation = {});
    PropertySchema& real(std::string key, double def, double min, double max, std::string doc,
                         std::string citation = {});
    PropertySchema& vec3(std::string key, glm::vec3 def, double min, double max, std::string doc,
                         std::string citation = {});
    PropertySchema& color(std::string key, glm::vec3 def, std::string doc,
                          std::string citation = {});
    PropertySchema& choice(std::string key, std::string def, std::vector<std::string> choices,
                           std::string doc, std::string citation = {});
    PropertySchema& text(std::string key, std::string def, std::string doc,
                         std::string citation = {});
    // Changes the default of a declared key (variants of one technique under other ids).
    PropertySchema& withDefault(const std::string& key, nlohmann::json value);

    const std::vector<PropertyDecl>& all() const { return decls_; }
    const PropertyDecl* find(const std::string& key) const;
    bool empty() const { return decls_.empty(); }
    std::vector<std::string> keys() const;

    // Validates `values` (a JSON object; null = no values) and fills in defaults. `where`
    // prefixes messages, e.g. "scene.json: /render/oit" -> "scene.json: /render/oit/bias: ...".
    // `owner` names what the keys belong to in the unknown-key message ("OIT technique
    // 'stochastic'"); `ignore` lists keys that belong to the caller (the technique's "type").
    Properties resolve(const nlohmann::json& values, const std::string& where,
                       const std::string& owner = {},
                       const std::vector<std::string>& ignore = {"type"}) const;
    // The defaults alone.
    Properties defaults() const;

    // {key: {type, default, range, doc, citation}} for `veil techniques --json`.
    nlohmann::json describe() const;

private:
    PropertySchema& add(PropertyDecl decl);
    std::vector<PropertyDecl> decls_;
};

// Effective values of a schema's properties (every key present). Getters of a key the
// schema does not declare, or of another type, are programming errors and throw.
class Properties {
public:
    Properties() = default;

    bool getBool(const std::string& key) const;
    int getInt(const std::string& key) const;
    float getFloat(const std::string& key) const;
    double getDouble(const std::string& key) const;
    glm::vec3 getVec3(const std::string& key) const;
    std::string getString(const std::string& key) const; // String and Enum

    // Sets a value, validated like resolve() does (for tests, tools and the viewer).
    Properties& set(const std::string& key, const nlohmann::json& value);

    const nlohmann::json& values() const { return values_; } // {key: value}

private:
    friend class PropertySchema;
    const nlohmann::json& at(const std::string& key, PropertyType type) const;
    std::vector<PropertyDecl> decls_;
    nlohmann::json values_ = nlohmann::json::object();
};

} // namespace veil
