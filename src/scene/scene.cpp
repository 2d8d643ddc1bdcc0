// Camera matrices, material classification, scene queries, command-line overrides and
// loading a scene file. The JSON schema itself is parsed in scene_json.cpp.
#include "scene/scene.h"
#include "scene/scene_document.h"

#include "base/error.h"
#include "base/log.h"
#include "base/text.h"
#include "scene/json_text.h"
#include "scene/scene_json.h"
#include "scene/timeline.h"

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>

namespace veil::scene {

glm::mat4 Camera::view() const { return glm::lookAt(position, target, up); }

glm::mat4 Camera::projection(float aspect) const {
    if (type == CameraType::Orthographic) {
        float h = 0.5f * orthoHeight;
        return glm::ortho(-h * aspect, h * aspect, -h, h, nearPlane, farPlane);
    }
    return glm::perspective(glm::radians(fovYDegrees), aspect, nearPlane, farPlane);
}

bool Material::isTransparent() const {
    return alpha < 1.0f || std::max({transmission.x, transmission.y, transmission.z}) > 0.0f ||
           coverageEdge > 0.0f;
}

bool Material::baseCoverageIsBinary() const {
    return coverageEdge > 0.0f && alpha == 1.0f &&
           std::max({transmission.x, transmission.y, transmission.z}) == 0.0f;
}

const Camera& Scene::camera(const std::string& name) const {
    VEIL_CHECK(!cameras.empty(), "scene '{}' has no camera", sourcePath.string());
    const std::string& wanted = name.empty() ? render.camera : name;
    if (wanted.empty()) return cameras.front();
    for (const Camera& c : cameras)
        if (c.name == wanted) return c;
    std::string known;
    for (const Camera& c : cameras)
        known += (known.empty() ? "" : ", ") + c.name;
    throw Error(fmt::format("scene '{}': no camera named '{}' (cameras: {})", sourcePath.string(),
                            wanted, known));
}

void Scene::bounds(glm::vec3& lo, glm::vec3& hi) const {
    lo = glm::vec3(std::numeric_limits<float>::max());
    hi = glm::vec3(std::numeric_limits<float>::lowest());
    bool any = false;
    for (const Object& o : objects) {
        if (o.mesh >= meshes.size() || meshes[o.mesh].positions.empty()) continue;
        glm::vec3 mlo, mhi;
        meshes[o.mesh].bounds(mlo, mhi);
        for (int corner = 0; corner < 8; ++corner) {
            glm::vec3 p((corner & 1) ? mhi.x : mlo.x, (corner & 2) ? mhi.y : mlo.y,
                        (corner & 4) ? mhi.z : mlo.z);
            glm::vec3 w = glm::vec3(o.transform * glm::vec4(p, 1.0f));
            lo = glm::min(lo, w);
            hi = glm::max(hi, w);
        }
        any = true;
    }
    if (!any) lo = hi = glm::vec3(0.0f);
}

namespace {

// A scene is JSON text: its first byte after white space and comments opens an object. Other
// files (a NanoVDB grid, an OpenVDB file without its extension, a mesh, an image) are named
// by their format rather than reported as a JSON parse error at line 1.
void checkSceneFormat(std::string_view text, const std::filesystem::path& path) {
    const std::size_t first = text.find_first_not_of(" \t\r\n");
    if (first == std::string_view::npos || text[first] == '{' || text[first] == '/') return;
    const auto startsWith = [&](std::string_view magic) {
        return text.substr(0, magic.size()) == magic;
    };
    const std::string ext = lowerExtension(path.string());
    std::string format;
    if (startsWith("NanoVDB") || ext == ".nvdb")
        format = "a NanoVDB grid (.nvdb), which veil does not read: convert it to OpenVDB "
                 "(.vdb, e.g. with nanovdb_convert) and give the .vdb";
    else if (ext == ".vdb")
        format = "an OpenVDB file: give it to veil render/view directly or as a scene's "
                 "volumes[].path";
    else if (startsWith(std::string_view("\x20\x42\x44\x56", 4)))
        format = "an OpenVDB file: name it *.vdb so veil reads it as a grid";
    else if (startsWith("\x89PNG") || startsWith("\x76\x2f\x31\x01") || ext == ".png" ||
             ext == ".exr")
        format = "an image, not a scene";
    else if (startsWith("glTF") || ext == ".obj" || ext == ".ply" || ext == ".glb" ||
             ext == ".gltf")
        format = "a mesh: reference it from a scene's objects, or voxelize it with veil voxelize";
    if (!format.empty())
        throw Error(fmt::format("'{}' is {} (veil reads scenes as .json and density grids as "
                                ".vdb)",
                                path.string(), format));
}

bool parseIndex(const std::string& s, std::size_t& out) {
    if (s.empty()) return false;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && ptr == s.data() + s.size();
}

} // namespace

void applyOverrides(nlohmann::json& doc, const std::vector<std::string>& overrides) {
    for (const std::string& arg : overrides) {
        const std::string ov = printable(arg, 200); // for messages: bounded, bad bytes as \xHH
        if (const auto bad = firstInvalidUtf8(arg))
            throw Error(fmt::format("override '{}': not valid UTF-8 (byte 0x{:02X} at offset {})",
                                    ov, static_cast<unsigned char>(arg[*bad]), *bad));
        auto eq = arg.find('=');
        VEIL_CHECK(eq != std::string::npos,
                   "override '{}': expected key=value, for example render.width=320", ov);
        std::string key = arg.substr(0, eq), text = arg.substr(eq + 1);
        VEIL_CHECK(!key.empty(), "override '{}': empty key before '='", ov);

        std::vector<std::string> parts;
        std::stringstream ss(key);
        for (std::string part; std::getline(ss, part, '.');)
            parts.push_back(part);
        if (key.back() == '.') parts.emplace_back();

        nlohmann::json* node = &doc;
        std::string walked;
        for (const std::string& part : parts) {
            VEIL_CHECK(!part.empty(), "override '{}': empty component in key '{}'", ov,
                       printable(key));
            if (node->is_array()) {
                std::size_t index = 0;
                VEIL_CHECK(parseIndex(part, index),
                           "override '{}': '{}' is an array, '{}' is not an index", ov, walked,
                           part);
                VEIL_CHECK(index < node->size(),
                           "override '{}': index {} out of range, '{}' has {} elements", ov, index,
                           walked, node->size());
                node = &(*node)[index];
            } else {
                // A typed object in its plain string form ("oit": "stochastic") opens into
                // {"type": "stochastic"} when a key below it is set (render.oit.samples=16).
                if (node->is_string()) *node = nlohmann::json{{"type", *node}};
                VEIL_CHECK(node->is_object() || node->is_null(),
                           "override '{}': '{}' is a {}, not an object or array", ov, walked,
                           node->type_name());
                node = &(*node)[part]; // creates missing object keys
            }
            walked += (walked.empty() ? "" : ".") + part;
        }
        // The value is JSON when it parses as JSON (numbers, true, [1,2,3]); else a string.
        if (const auto at = excessiveNestingAt(text))
            throw Error(fmt::format("override '{}': value nested deeper than {} levels at {}", ov,
                                    kMaxJsonDepth, lineColumn(text, *at)));
        nlohmann::json value = nlohmann::json::parse(text, nullptr, false);
        if (value.is_discarded()) value = text;
        *node = std::move(value);
        if (log::enabled(log::Level::Debug))
            log::debug("override {} = {}", printable(key), describeJson(*node, 200));
    }
}

void applyTechniqueChoice(nlohmann::json& doc, const TechniqueChoice& choice) {
    const RenderSettings defaults;
    const auto choose = [&doc](const char* key, const std::string& name,
                               const std::string& fallback) {
        if (name.empty() || !doc.is_object()) return;
        nlohmann::json& render = doc["render"];
        if (!render.is_object() && !render.is_null()) return; // the parser names the problem
        // Absent (the default technique) or properties without "type": the default.
        if (!render.is_object() || !render.contains(key)) {
            if (name != fallback) render[key] = name;
            if (render.is_null()) doc.erase("render");
            return;
        }
        nlohmann::json& current = render[key];
        std::string named = fallback;
        if (current.is_string()) named = current.get<std::string>();
        if (current.is_object() && current.contains("type") && current["type"].is_string())
            named = current["type"].get<std::string>();
        if (named != name) current = name;
    };
    choose("oit", choice.oit, defaults.oit);
    choose("shadows", choice.shadows, defaults.shadows);
}

namespace {

// An animated scene as one frame: time.frame, else its first.
Scene atDefaultFrame(AnimatedScene&& s, const std::string& source) {
    if (!s.timeline.animated()) return std::move(s.scene);
    try {
        return sceneAtFrame(s, defaultFrame(s.timeline));
    } catch (const Error& e) {
        throw Error(fmt::format("{}: {}", source, e.what()));
    }
}

} // namespace

AnimatedScene parseAnimatedScene(const nlohmann::json& doc, const std::filesystem::path& baseDir) {
    AnimatedScene s;
    s.scene = detail::parseSceneDocument(doc, baseDir, "<scene>", &s.timeline);
    return s;
}

Scene parseScene(const nlohmann::json& doc, const std::filesystem::path& baseDir) {
    return atDefaultFrame(parseAnimatedScene(doc, baseDir), "<scene>");
}

nlohmann::json readSceneDocument(const std::filesystem::path& path) {
    // /dev/zero or a FIFO would be read forever: only regular files of a sane size.
    constexpr std::uintmax_t kMaxSceneBytes = std::uintmax_t(256) << 20;
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    VEIL_CHECK(!std::filesystem::is_directory(status),
               "cannot open scene file '{}': not a regular file but a folder", path.string());
    VEIL_CHECK(!std::filesystem::exists(status) || std::filesystem::is_regular_file(status),
               "cannot open scene file '{}': not a regular file", path.string());
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    VEIL_CHECK(ec || bytes <= kMaxSceneBytes,
               "cannot open scene file '{}': {} bytes is more than a scene's limit of 256 MiB",
               path.string(), bytes);
    std::ifstream in(path, std::ios::binary);
    VEIL_CHECK(in.good() && !std::filesystem::is_directory(path), "cannot open scene file '{}'",
               path.string());
    std::stringstream text;
    text << in.rdbuf();

    checkSceneFormat(text.str(), path);
    // Comments (// and /* */) are allowed so example scenes can explain themselves.
    return parseJsonText(text.str(), path.string());
}

void applySceneOverrides(nlohmann::json& doc, const std::vector<std::string>& overrides,
                         const std::string& source, const TechniqueChoice& choice) {
    try {
        applyTechniqueChoice(doc, choice);
        applyOverrides(doc, overrides);
    } catch (const Error& e) {
        throw Error(fmt::format("{}: {}", source, e.what()));
    } catch (const nlohmann::json::exception& e) {
        throw Error(fmt::format("{}: --set: {}", source, jsonProblem(e)));
    }
}

namespace {

AnimatedScene parseAnimated(const nlohmann::json& doc, const std::filesystem::path& baseDir,
                            const std::string& source) {
    AnimatedScene s;
    try {
        s.scene = detail::parseSceneDocument(doc, baseDir, source, &s.timeline);
    } catch (const nlohmann::json::exception& e) {
        // The parser checks types before reading values; this is a last line, not the plan.
        throw Error(fmt::format("{}: {}", source, jsonProblem(e)));
    }
    return s;
}

} // namespace

Scene parseScene(const nlohmann::json& doc, const std::filesystem::path& baseDir,
                 const std::string& source) {
    return atDefaultFrame(parseAnimated(doc, baseDir, source), source);
}

AnimatedScene loadAnimatedScene(const std::filesystem::path& path,
                                const std::vector<std::string>& overrides,
                                const TechniqueChoice& choice) {
    nlohmann::json doc = readSceneDocument(path);
    applySceneOverrides(doc, overrides, path.string(), choice);
    const std::filesystem::path absolute = std::filesystem::absolute(path);
    AnimatedScene scene = parseAnimated(doc, absolute.parent_path(), path.string());
    scene.scene.sourcePath = absolute;
    return scene;
}

Scene loadScene(const std::filesystem::path& path, const std::vector<std::string>& overrides,
                const TechniqueChoice& choice) {
    return atDefaultFrame(loadAnimatedScene(path, overrides, choice), path.string());
}

} // namespace veil::scene
