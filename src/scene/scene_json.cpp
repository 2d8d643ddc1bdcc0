// The JSON scene format (docs/scene-format.md). Every object declares its keys up front, so
// a misspelt key is reported with the keys that would have been accepted; every error names
// the file and the JSON pointer of the offending value.
#include "scene/scene_json.h"

#include "base/error.h"
#include "base/log.h"
#include "scene/animation_json.h"
#include "scene/json_reader.h"
#include "scene/json_text.h"
#include "scene/scene_values.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <system_error>
#include <type_traits>
#include <utility>
#include <variant>

namespace veil::scene::detail {

namespace {

// Reads the declared values (scene_values.h) of a document of type `typeIndex` into `s`, with
// the ranges and messages of json_reader.h.
template <class S>
void readValues(const Obj& o, const std::vector<ValueDecl<S>>& decls, S& s, int typeIndex = 0) {
    for (const ValueDecl<S>& d : decls) {
        if (!(d.acceptedBy & typeBit(typeIndex))) continue;
        const Range r{d.accepted.lo, d.accepted.hi, d.accepted.loOpen, d.accepted.hiOpen};
        std::visit(
            [&](auto member) {
                auto& field = s.*member;
                using T = std::decay_t<decltype(field)>;
                if constexpr (std::is_same_v<T, glm::vec3>)
                    field = o.vec<3>(d.key, field, r, d.scalarAllowed);
                else if constexpr (std::is_same_v<T, float>)
                    field = o.num(d.key, field, r);
                else if constexpr (std::is_same_v<T, bool>)
                    field = o.boolean(d.key, field);
                else if constexpr (std::is_same_v<T, std::string>)
                    field = o.str(d.key, field, d.choices);
                else {
                    field = static_cast<T>(o.integer(d.key, static_cast<long long>(field),
                                                     static_cast<long long>(d.accepted.lo),
                                                     static_cast<long long>(d.accepted.hi)));
                    if (d.refused && static_cast<long long>(field) == *d.refused)
                        fail(o.ctx(), o.ptr(d.key), d.refusedMessage);
                }
            },
            d.field);
    }
}

// The keys a document of type `typeIndex` accepts: `before`, the declared values with `extra`
// after the value `after` (the order of the "unknown key (known: ...)" message).
template <class S>
std::vector<std::string>
keysOf(const std::vector<ValueDecl<S>>& decls, int typeIndex, std::vector<std::string> before,
       const std::vector<std::pair<std::string, std::vector<std::string>>>& extra = {}) {
    std::vector<std::string> keys = std::move(before);
    for (const ValueDecl<S>& d : decls) {
        if (!(d.acceptedBy & typeBit(typeIndex))) continue;
        keys.push_back(d.key);
        for (const auto& [after, more] : extra)
            if (after == d.key) keys.insert(keys.end(), more.begin(), more.end());
    }
    return keys;
}

// T * Rz * Ry * Rx * S (rotations applied X, then Y, then Z), or a column-major matrix.
glm::mat4 parseTransform(const Context& ctx, const json& j, const std::string& ptr) {
    if (j.is_object() && j.contains("matrix") && j.size() > 1)
        fail(ctx, ptr, "'matrix' cannot be combined with translate/rotate/scale");
    if (j.is_object() && j.contains("matrix")) {
        Obj o(ctx, j, ptr, {"matrix"});
        const json& m = o.require("matrix");
        if (!m.is_array() || m.size() != 16)
            fail(ctx, o.ptr("matrix"),
                 fmt::format("expected an array of 16 numbers, got {}", show(m)));
        float values[16];
        for (int i = 0; i < 16; ++i)
            values[i] = float(number(ctx, m[i], child(o.ptr("matrix"), i), kAny));
        return glm::make_mat4(values);
    }
    Obj o(ctx, j, ptr, {"translate", "rotate", "scale"});
    glm::vec3 t = o.vec<3>("translate", glm::vec3(0.0f));
    glm::vec3 r = o.vec<3>("rotate", glm::vec3(0.0f));
    glm::vec3 s = o.vec<3>("scale", glm::vec3(1.0f), kAny, true);
    if (s.x == 0.0f || s.y == 0.0f || s.z == 0.0f)
        fail(ctx, o.ptr("scale"), "scale components must not be zero");
    glm::mat4 m = glm::translate(glm::mat4(1.0f), t);
    m = glm::rotate(m, glm::radians(r.z), glm::vec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(r.y), glm::vec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(r.x), glm::vec3(1, 0, 0));
    return glm::scale(m, s);
}

// `key`: NAME or {"type": NAME, property: value, ...}; the properties are checked against the
// technique's declared schema when the frame creates it (src/oit, src/shadows).
void parseTechniqueChoice(const Obj& o, const char* key, std::string& name,
                          nlohmann::json& properties, std::string& where) {
    if (const json* t = o.get(key); t && t->is_object()) {
        // No "type": the default technique with these properties (--set render.shadows.size=512
        // on a scene that names no technique).
        if (const json* type = t->contains("type") ? &(*t)["type"] : nullptr) {
            if (!type->is_string())
                fail(o.ctx(), o.ptr(key) + "/type", "expected the technique name as a string");
            name = type->get<std::string>();
        }
        properties = *t;
        properties.erase("type");
    } else {
        name = o.str(key, name);
    }
    where = fmt::format("{}: {}", o.ctx().source, o.ptr(key));
    if (name.empty()) fail(o.ctx(), o.ptr(key), "technique name must not be empty");
}

// Every declared value first (scene_values.cpp), then the technique choices.
void parseRender(const Obj& o, RenderSettings& r) {
    readValues(o, renderValueDecls(), r);
    r.camera = o.str("camera", r.camera);
    parseTechniqueChoice(o, "oit", r.oit, r.oitProperties, r.oitWhere);
    parseTechniqueChoice(o, "shadows", r.shadows, r.shadowProperties, r.shadowsWhere);
    // Ambient obscurance (src/frame/ao): an object of properties, checked against the pass's
    // declared schema when the frame is built.
    if (const json* ao = o.get("ao")) {
        if (!ao->is_object()) fail(o.ctx(), o.ptr("ao"), "expected an object of AO properties");
        r.aoProperties = *ao;
        r.aoWhere = fmt::format("{}: {}", o.ctx().source, o.ptr("ao"));
    }
    // The path tracer's properties (src/integrators/path_tracer.h), checked against its schema
    // when it runs.
    if (const json* pt = o.get("pathtraced")) {
        if (!pt->is_object())
            fail(o.ctx(), o.ptr("pathtraced"), "expected an object of path tracer properties");
        r.pathtracedProperties = *pt;
        r.pathtracedWhere = fmt::format("{}: {}", o.ctx().source, o.ptr("pathtraced"));
    }
    // Legacy keys of the opaque shadow map, kept as aliases of the shadow technique's
    // properties (every technique has an opaque map: src/shadows/opaque/opaque.h).
    for (const auto& [legacy, key] :
         {std::pair<const char*, const char*>{"shadow_map_size", "size"},
          {"shadow_bias", "bias"},
          {"pcf_radius", "pcf_radius"}}) {
        const json* v = o.get(legacy);
        if (!v) continue;
        if (r.shadowProperties.is_object() && r.shadowProperties.contains(key))
            fail(o.ctx(), o.ptr(legacy),
                 fmt::format("set twice: here and as {}/{} (use only the latter)", o.ptr("shadows"),
                             key));
        if (!r.shadowProperties.is_object()) r.shadowProperties = json::object();
        r.shadowProperties[key] = *v;
    }
}

Camera parseCamera(const Context& ctx, const json& j, const std::string& ptr, std::size_t i,
                   CameraAnimation& animation) {
    Camera c;
    c.name = fmt::format("camera{}", i);
    std::string type = j.is_object() && j.contains("type") && j["type"].is_string()
                           ? j["type"].get<std::string>()
                           : "perspective";
    const CameraType peeked =
        type == "orthographic" ? CameraType::Orthographic : CameraType::Perspective;
    std::vector<std::string> known = keysOf(cameraValueDecls(), int(peeked), {"name", "type"});
    known.insert(known.end(), cameraAnimationKeys().begin(), cameraAnimationKeys().end());
    Obj o(ctx, j, ptr, known);
    c.name = o.str("name", c.name);
    c.type = o.str("type", "perspective", {"perspective", "orthographic"}) == "orthographic"
                 ? CameraType::Orthographic
                 : CameraType::Perspective;
    readValues(o, cameraValueDecls(), c, int(c.type));
    parseCameraAnimation(o, c, animation);
    if (c.farPlane <= c.nearPlane)
        fail(ctx, o.ptr("far"),
             fmt::format("far ({}) must be greater than near ({})", c.farPlane, c.nearPlane));
    glm::vec3 dir = c.target - c.position;
    if (glm::length(dir) == 0.0f) fail(ctx, o.ptr("target"), "target equals position");
    // The view matrix is built in float: a length that overflows makes it NaN or zero.
    if (!std::isfinite(glm::length(dir)))
        fail(ctx, o.ptr("target"), "target - position must have a length that fits a 32-bit float");
    if (!std::isfinite(glm::length(c.up)))
        fail(ctx, o.ptr("up"), "up must have a length that fits a 32-bit float");
    if (glm::length(c.up) == 0.0f ||
        glm::length(glm::cross(glm::normalize(dir), glm::normalize(c.up))) < 1e-6f)
        fail(ctx, o.ptr("up"), "up must be non-zero and not parallel to the view direction");
    return c;
}

// Normalized in double: in float, |(1e30, 1e30, 0)|^2 overflows and the result is zero.
glm::vec3 unitDirection(const Context& ctx, glm::vec3 d, const std::string& ptr, const char* what) {
    const glm::dvec3 dd(d);
    const double len = glm::length(dd);
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z) || len == 0.0)
        fail(ctx, ptr, fmt::format("{} must be a non-zero finite vector", what));
    return glm::vec3(dd / len);
}

Light parseLight(const Context& ctx, const json& j, const std::string& ptr, std::size_t i,
                 LightAnimation& animation) {
    Light l;
    l.name = fmt::format("light{}", i);
    std::string type = j.is_object() && j.contains("type") && j["type"].is_string()
                           ? j["type"].get<std::string>()
                           : "directional";
    const LightType peeked = type == "spot"    ? LightType::Spot
                             : type == "point" ? LightType::Point
                                               : LightType::Directional;
    std::vector<std::pair<std::string, std::vector<std::string>>> aim;
    if (peeked != LightType::Point) aim.push_back({"position", {"direction", "target"}});
    std::vector<std::string> known = keysOf(lightValueDecls(), int(peeked), {"name", "type"}, aim);
    known.insert(known.end(), lightAnimationKeys().begin(), lightAnimationKeys().end());
    Obj o(ctx, j, ptr, known);
    l.name = o.str("name", l.name);
    std::string t = o.str("type", "directional", {"directional", "spot", "point"});
    l.type = t == "spot"    ? LightType::Spot
             : t == "point" ? LightType::Point
                            : LightType::Directional;
    readValues(o, lightValueDecls(), l, int(l.type));
    if (o.has("direction") && o.has("target"))
        fail(ctx, o.ptr("target"), "give either direction or target, not both");
    if (o.has("target")) {
        glm::vec3 d = o.vec<3>("target", glm::vec3(0.0f)) - l.position;
        if (d == glm::vec3(0.0f)) fail(ctx, o.ptr("target"), "target equals position");
        l.direction = unitDirection(ctx, d, o.ptr("target"), "target - position");
    } else if (o.has("direction")) {
        glm::vec3 d = o.vec<3>("direction", l.direction);
        if (d == glm::vec3(0.0f)) fail(ctx, o.ptr("direction"), "direction must not be zero");
        l.direction = unitDirection(ctx, d, o.ptr("direction"), "direction");
    }
    if (l.outerConeDegrees < l.innerConeDegrees)
        fail(ctx, o.ptr("outer_cone"),
             fmt::format("outer_cone ({}) must be >= inner_cone ({})", l.outerConeDegrees,
                         l.innerConeDegrees));
    parseLightAnimation(o, l, animation);
    return l;
}

Material parseMaterial(const Context& ctx, const json& j, const std::string& ptr,
                       const std::string& name) {
    Obj o(ctx, j, ptr, keysOf(materialValueDecls(), 0, {}));
    Material m;
    m.name = name;
    readValues(o, materialValueDecls(), m);
    return m;
}

// Generated shapes of one scene make at most this many triangles together. Each shape's
// parameters are bounded, but a few hundred bytes of JSON could still ask for billions of
// triangles (a 4096 x 4096 sphere is 33 M, 2^26 particles 134 M; objects multiply them):
// minutes and tens of GB before anything is rendered. 16.7 M triangles are about 0.5 GB;
// the largest scenes of the repository use 1.2 M (tests/fuzz/regressions/scene/).
constexpr std::uint64_t kMaxGeneratedTriangles = std::uint64_t(1) << 24;

// Charges a shape's triangles to the scene's budget before the shape is made.
void chargeTriangles(const Context& ctx, const std::string& ptr, std::uint64_t& used,
                     std::uint64_t triangles) {
    if (triangles > kMaxGeneratedTriangles - used)
        fail(ctx, ptr,
             fmt::format("this shape makes {} triangles; generated shapes may make {} in all "
                         "and the shapes before it make {} (use fewer segments, subdivisions or "
                         "particles)",
                         triangles, kMaxGeneratedTriangles, used));
    used += triangles;
}

MeshData parseShape(const Context& ctx, const json& j, const std::string& ptr,
                    int geometryBudgetMiB, std::uint64_t& trianglesUsed) {
    static const std::vector<std::string> types = {"plane", "box", "sphere", "torus", "particles"};
    if (!j.is_object()) fail(ctx, ptr, fmt::format("expected an object, got {}", show(j)));
    if (!j.contains("type"))
        fail(ctx, ptr, fmt::format("missing required key 'type' ({})", joined(types)));
    // The type decides which keys are known, so it is checked before the object is opened.
    const json& t = j["type"];
    if (!t.is_string())
        fail(ctx, child(ptr, "type"), fmt::format("expected a string, got {}", show(t)));
    const std::string type = t.get<std::string>();
    if (std::find(types.begin(), types.end(), type) == types.end())
        fail(ctx, child(ptr, "type"),
             fmt::format("unknown value '{}' (allowed: {})", type, joined(types)));
    const int kMaxSeg = 4096;
    if (type == "plane") {
        Obj o(ctx, j, ptr, {"type", "size", "subdivisions"});
        glm::vec2 size = o.vec<2>("size", glm::vec2(1.0f), kPositive, true);
        int sub = int(o.integer("subdivisions", 1, 1, kMaxSeg));
        chargeTriangles(ctx, ptr, trianglesUsed, 2 * std::uint64_t(sub) * std::uint64_t(sub));
        return at(ctx, ptr, [&] { return makePlane(size, sub); });
    }
    if (type == "box") {
        Obj o(ctx, j, ptr, {"type", "size"});
        glm::vec3 size = o.vec<3>("size", glm::vec3(1.0f), kPositive, true);
        chargeTriangles(ctx, ptr, trianglesUsed, 12);
        return at(ctx, ptr, [&] { return makeBox(size); });
    }
    if (type == "sphere") {
        Obj o(ctx, j, ptr, {"type", "radius", "segments", "rings"});
        float r = o.num("radius", 1.0f, kPositive);
        int seg = int(o.integer("segments", 48, 3, kMaxSeg));
        int rings = int(o.integer("rings", 24, 2, kMaxSeg));
        chargeTriangles(ctx, ptr, trianglesUsed, 2 * std::uint64_t(seg) * std::uint64_t(rings));
        return at(ctx, ptr, [&] { return makeSphere(r, seg, rings); });
    }
    if (type == "torus") {
        Obj o(ctx, j, ptr,
              {"type", "major_radius", "minor_radius", "major_segments", "minor_segments"});
        float major = o.num("major_radius", 1.0f, kPositive);
        float minor = o.num("minor_radius", 0.25f, kPositive);
        if (minor >= major)
            fail(
                ctx, o.ptr("minor_radius"),
                fmt::format("minor_radius ({}) must be less than major_radius ({})", minor, major));
        int ms = int(o.integer("major_segments", 48, 3, kMaxSeg));
        int ns = int(o.integer("minor_segments", 24, 3, kMaxSeg));
        chargeTriangles(ctx, ptr, trianglesUsed, 2 * std::uint64_t(ms) * std::uint64_t(ns));
        return at(ctx, ptr, [&] { return makeTorus(major, minor, ms, ns); });
    }
    Obj o(ctx, j, ptr, {"type", "count", "radius", "particle_size", "seed"});
    int count = int(o.integer("count", 1000, 1, 1 << 26));
    // 4 vertices (position, normal, uv, size: 36 bytes) and 6 indices (24 bytes) per particle,
    // held once on the CPU and once on the GPU: refuse before allocating.
    const double mib = double(count) * (4 * 36 + 24) / (1024.0 * 1024.0);
    if (mib > geometryBudgetMiB)
        fail(ctx, o.ptr("count"),
             fmt::format("{} particles need an estimated {:.0f} MiB of vertex data (on the CPU "
                         "and again on the GPU), over render.geometry_budget_mib = {}",
                         count, mib, geometryBudgetMiB));
    float radius = o.num("radius", 1.0f, kPositive);
    float size = o.num("particle_size", 0.02f, kPositive);
    auto seed = std::uint32_t(o.integer("seed", 1, 0, std::numeric_limits<std::uint32_t>::max()));
    chargeTriangles(ctx, ptr, trianglesUsed, 2 * std::uint64_t(count));
    return at(ctx, ptr, [&] { return makeParticleCloud(count, radius, size, seed); });
}

// Scene assembly state shared by the object parser.
struct Builder {
    Scene& scene;
    std::map<std::string, std::uint32_t> materialIndex;
    // Mesh files already loaded: (mesh index, name, material name or empty) per file mesh.
    struct FileMesh {
        std::uint32_t mesh;
        std::string name;
        std::string material;
    };
    std::map<std::string, std::vector<FileMesh>> files;
    std::uint64_t generatedTriangles = 0; // charged by parseShape, kMaxGeneratedTriangles

    std::uint32_t addMaterial(Material m) {
        auto it = materialIndex.find(m.name);
        if (it != materialIndex.end()) return it->second;
        auto index = std::uint32_t(scene.materials.size());
        materialIndex[m.name] = index;
        scene.materials.push_back(std::move(m));
        return index;
    }
};

void parseObject(const Context& ctx, const json& j, const std::string& ptr, std::size_t i,
                 Builder& b) {
    Obj o(ctx, j, ptr, {"name", "shape", "mesh", "material", "transform", "shadows"});
    if (o.has("shape") == o.has("mesh"))
        fail(ctx, ptr, "an object needs exactly one of 'shape' and 'mesh'");
    Object base;
    base.name = o.str("name", fmt::format("object{}", i));
    base.castShadows = o.boolean("shadows", true);
    if (const json* t = o.get("transform"))
        base.transform = parseTransform(ctx, *t, o.ptr("transform"));

    std::optional<std::uint32_t> material;
    if (o.has("material")) {
        std::string name = o.str("material", "");
        auto it = b.materialIndex.find(name);
        if (it == b.materialIndex.end()) {
            std::vector<std::string> known;
            for (const auto& [n, idx] : b.materialIndex)
                known.push_back(n);
            fail(ctx, o.ptr("material"),
                 fmt::format("unknown material '{}' (materials: {})", name,
                             known.empty() ? "none" : joined(known)));
        }
        material = it->second;
    }

    if (const json* shape = o.get("shape")) {
        if (!material) fail(ctx, ptr, "missing required key 'material' (required for shapes)");
        base.mesh = std::uint32_t(b.scene.meshes.size());
        base.material = *material;
        b.scene.meshes.push_back(parseShape(
            ctx, *shape, o.ptr("shape"), b.scene.render.geometryBudgetMiB, b.generatedTriangles));
        b.scene.objects.push_back(base);
        return;
    }

    fs::path path = resolvePath(o, "mesh", "mesh file");
    auto cached = b.files.find(path.string());
    if (cached == b.files.end()) {
        std::vector<LoadedMesh> loaded = at(ctx, o.ptr("mesh"), [&] { return loadMeshFile(path); });
        std::vector<Builder::FileMesh> entries;
        const std::string stem = path.stem().string();
        for (LoadedMesh& lm : loaded) {
            Builder::FileMesh fm{std::uint32_t(b.scene.meshes.size()), lm.mesh.name, {}};
            if (lm.material) {
                fm.material = stem + "/" + lm.material->name;
                // A scene material of the same name takes precedence over the file's.
                if (!b.materialIndex.count(fm.material)) {
                    Material m = *lm.material;
                    m.name = fm.material;
                    b.addMaterial(std::move(m));
                }
            }
            b.scene.meshes.push_back(std::move(lm.mesh));
            entries.push_back(std::move(fm));
        }
        cached = b.files.emplace(path.string(), std::move(entries)).first;
    }
    for (const Builder::FileMesh& fm : cached->second) {
        Object obj = base;
        obj.mesh = fm.mesh;
        if (cached->second.size() > 1) obj.name = base.name + "/" + fm.name;
        if (material)
            obj.material = *material;
        else if (!fm.material.empty())
            obj.material = b.materialIndex.at(fm.material);
        else
            obj.material = b.addMaterial(Material{}); // "default", or the scene's "default"
        b.scene.objects.push_back(std::move(obj));
    }
}

VolumeRef parseVolume(const Context& ctx, const json& j, const std::string& ptr, std::size_t i,
                      std::optional<FileSequence>& sequence) {
    std::vector<std::string> known =
        keysOf(volumeValueDecls(), 0,
               {"name", "path", "procedural", "size", "voxel_size", "seed", "grid", "transform"});
    known.insert(known.end(), sequenceKeys().begin(), sequenceKeys().end());
    Obj o(ctx, j, ptr, known);
    VolumeRef v;
    v.name = o.str("name", fmt::format("volume{}", i));
    if (o.get("path") && o.get("procedural"))
        fail(ctx, o.ptr("procedural"), "give either path or procedural, not both");
    if (o.get("procedural")) {
        v.procedural =
            o.str("procedural", "", {"box", "sphere", "smoke-ball", "noise-cloud", "homogeneous"});
        // Positions are bounded by +-1e6 (cameras, lights): a larger volume cannot be seen from
        // outside, and 1e30 made the voxel-count guard coarsen to 1e23-unit voxels and march
        // for minutes.
        v.size = o.vec<3>("size", v.size, Range{0.0, 1e6, true, false}, true);
        v.voxelSize = o.num("voxel_size", v.voxelSize, Range{1e-4, 1e4, true, true});
        v.seed = static_cast<std::uint32_t>(o.integer("seed", 1, 0, 1 << 30));
    } else {
        o.require("path");
        if (!parseVolumeSequence(o, v, sequence)) v.path = resolvePath(o, "path", "volume file");
    }
    v.grid = o.str("grid", v.grid);
    if (v.grid.empty()) fail(ctx, o.ptr("grid"), "grid name must not be empty");
    if (const json* t = o.get("transform"))
        v.transform = parseTransform(ctx, *t, o.ptr("transform"));
    readValues(o, volumeValueDecls(), v);
    for (const char* key : {"emission_grid", "temperature_grid"}) {
        if (o.get(key) && v.path.empty())
            fail(ctx, o.ptr(key), "a procedural volume has no file to read a grid from");
        // "" would silently mean no emission: leave the key out for that.
        if (const json* g = o.get(key); g && g->is_string() && g->get<std::string>().empty())
            fail(ctx, o.ptr(key),
                 fmt::format("{} must name a grid of the volume's file (leave the key out for "
                             "none)",
                             key));
    }
    if (!v.emissionGrid.empty() && !v.temperatureGrid.empty())
        fail(ctx, o.ptr("temperature_grid"), "give either emission_grid or temperature_grid");
    return v;
}

template <typename T>
void checkUniqueNames(const Context& ctx, const std::vector<T>& items, const std::string& ptr) {
    for (std::size_t a = 0; a < items.size(); ++a)
        for (std::size_t c = 0; c < a; ++c)
            if (items[a].name == items[c].name)
                fail(ctx, child(child(ptr, a), "name"),
                     fmt::format("duplicate name '{}' (also {})", items[a].name, child(ptr, c)));
}

} // namespace

Scene parseSceneDocument(const json& doc, const fs::path& baseDir, const std::string& source,
                         Timeline* timeline) {
    Context ctx{source, baseDir};
    Scene scene;
    Obj root(ctx, doc, "",
             {"render", "time", "cameras", "lights", "materials", "objects", "volumes"});
    Timeline time;
    if (const json* t = root.get("time"))
        parseTime(Obj(ctx, *t, root.ptr("time"), timeKeys()), time.time);

    if (const json* r = root.get("render"))
        parseRender(Obj(ctx, *r, root.ptr("render"),
                        keysOf(renderValueDecls(), 0, {},
                               {{"height", {"camera", "oit", "shadows", "ao", "pathtraced"}},
                                {"tonemap", {"shadow_map_size", "shadow_bias", "pcf_radius"}}})),
                    scene.render);

    forEach(root, "cameras", [&](const json& j, const std::string& p, std::size_t i) {
        scene.cameras.push_back(parseCamera(ctx, j, p, i, time.cameras.emplace_back()));
    });
    if (scene.cameras.empty())
        fail(ctx, root.ptr("cameras"), "the scene needs at least one camera");
    checkUniqueNames(ctx, scene.cameras, root.ptr("cameras"));
    if (!scene.render.camera.empty()) {
        bool found = std::any_of(scene.cameras.begin(), scene.cameras.end(),
                                 [&](const Camera& c) { return c.name == scene.render.camera; });
        if (!found) {
            std::vector<std::string> names;
            for (const Camera& c : scene.cameras)
                names.push_back(c.name);
            fail(ctx, "/render/camera",
                 fmt::format("unknown camera '{}' (cameras: {})", scene.render.camera,
                             joined(names)));
        }
    }

    forEach(root, "lights", [&](const json& j, const std::string& p, std::size_t i) {
        scene.lights.push_back(parseLight(ctx, j, p, i, time.lights.emplace_back()));
    });

    Builder builder{scene, {}, {}, 0};
    if (const json* mats = root.get("materials")) {
        if (!mats->is_object())
            fail(ctx, root.ptr("materials"),
                 fmt::format("expected an object of name: material, got {}", show(*mats)));
        for (const auto& item : mats->items()) {
            if (item.key().empty())
                fail(ctx, child(root.ptr("materials"), ""), "material name must not be empty");
            builder.addMaterial(parseMaterial(
                ctx, item.value(), child(root.ptr("materials"), item.key()), item.key()));
        }
    }

    forEach(root, "objects", [&](const json& j, const std::string& p, std::size_t i) {
        parseObject(ctx, j, p, i, builder);
    });
    forEach(root, "volumes", [&](const json& j, const std::string& p, std::size_t i) {
        scene.volumes.push_back(parseVolume(ctx, j, p, i, time.volumes.emplace_back()));
    });
    log::debug("{}: {} cameras, {} lights, {} materials, {} objects, {} meshes, {} volumes", source,
               scene.cameras.size(), scene.lights.size(), scene.materials.size(),
               scene.objects.size(), scene.meshes.size(), scene.volumes.size());
    if (timeline) *timeline = std::move(time);
    return scene;
}

} // namespace veil::scene::detail
