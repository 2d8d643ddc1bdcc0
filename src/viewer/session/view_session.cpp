#include "viewer/session/view_session.h"

#include "grid/vdb_scene.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/log.h"
#include "base/text.h"
#include "oit/technique.h"
#include "scene/json_text.h"
#include "scene/scene_values.h"
#include "sequence/prefetch.h"
#include "shadows/technique.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace veil::session {

namespace fs = std::filesystem;

void Orbit::from(const scene::Camera& c) {
    target = c.target;
    const glm::vec3 d = c.position - c.target;
    distance = std::max(glm::length(d), 1e-4f);
    yaw = std::atan2(d.x, d.z);
    pitch = std::asin(glm::clamp(d.y / distance, -1.0f, 1.0f));
}

void Orbit::apply(scene::Camera& c) const {
    const glm::vec3 dir(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                        std::cos(pitch) * std::cos(yaw));
    c.position = target + dir * distance;
    c.target = target;
    c.up = glm::vec3(0, 1, 0);
}

void Orbit::pan(float dx, float dy) {
    const glm::vec3 forward(-std::cos(pitch) * std::sin(yaw), -std::sin(pitch),
                            -std::cos(pitch) * std::cos(yaw));
    const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0, 1, 0)));
    const glm::vec3 up = glm::cross(right, forward);
    const glm::dvec3 moved =
        glm::dvec3(target) + glm::dvec3(right * dx + up * dy) * double(distance);
    target = glm::vec3(glm::clamp(moved, -double(kMaxExtent), double(kMaxExtent)));
}

namespace {

bool startsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// "lights.3.intensity" -> {"lights", "3", "intensity"}
std::vector<std::string> splitKey(const std::string& key) {
    std::vector<std::string> parts;
    std::stringstream ss(key);
    for (std::string part; std::getline(ss, part, '.');)
        parts.push_back(part);
    return parts;
}

std::string keyOf(const std::string& keyValue) { return keyValue.substr(0, keyValue.find('=')); }

// A float as the double it is, printed shortest: JSON -> double -> float gives it back exactly.
std::string exact(float f) { return fmt::format("{}", static_cast<double>(f)); }
std::string exact(const glm::vec3& v) {
    return fmt::format("[{},{},{}]", exact(v.x), exact(v.y), exact(v.z));
}

// Single quotes for a POSIX shell.
std::string shellQuote(const std::string& s) {
    if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                          "0123456789._-/=+,:") == std::string::npos)
        return s;
    std::string q = "'";
    for (char c : s) {
        if (c == '\'')
            q.append("'\\''");
        else
            q.push_back(c);
    }
    q.push_back('\'');
    return q;
}

} // namespace

scene::EditEffect overrideEditEffect(const std::string& key) {
    using scene::EditEffect;
    const std::vector<std::string> p = splitKey(key);
    if (p.size() == 2 && p[0] == "render")
        return scene::editEffect(scene::renderValueDecls(), p[1]);
    // A light's or a material's value, or one component of it (lights.0.color.1).
    if (p.size() >= 3 && p[0] == "lights")
        return p[2] == "direction" || p[2] == "target"
                   ? scene::kLightAimEdit
                   : scene::editEffect(scene::lightValueDecls(), p[2]);
    if (p.size() >= 3 && p[0] == "materials")
        return scene::editEffect(scene::materialValueDecls(), p[2]);
    if (p.size() == 3 && p[0] == "volumes") // the session checks that the volume is a grid
        return scene::editEffect(scene::volumeValueDecls(), p[2]);
    return EditEffect::Rebuild;
}

OverrideScope classifyOverride(const std::string& key) {
    const std::vector<std::string> p = splitKey(key);
    if (p.empty()) return OverrideScope::Renderer;
    if (p[0] == "cameras") return OverrideScope::Camera;
    if (p[0] == "render" && p.size() >= 2) {
        if (p[1] == "oit") return OverrideScope::Oit;
        if (p[1] == "width" || p[1] == "height") return OverrideScope::Size;
    }
    return overrideEditEffect(key) == scene::EditEffect::Rebuild ? OverrideScope::Renderer
                                                                 : OverrideScope::Live;
}

ViewSession::ViewSession(const gpu::ContextInfo& context, fs::path scenePath,
                         std::vector<std::string> overrides, std::string camera, int width,
                         int height)
    : context_(context), cameraName_(std::move(camera)), width_(width), height_(height) {
    std::vector<std::string> list;
    for (const std::string& o : overrides)
        addOverride(list, o);
    rebuild(scenePath, list); // throws: there is nothing to show without a first scene
    scenePath_ = std::move(scenePath);
    overrides_ = std::move(list);
}

ViewSession::~ViewSession() = default;

std::unique_ptr<scene::Scene> ViewSession::loadWith(const fs::path& path,
                                                    const std::vector<std::string>& ov) const {
    if (lowerExtension(path.string()) == ".vdb")
        return std::make_unique<scene::Scene>(vdb::sceneForVdb(path, "", ov).scene);
    return std::make_unique<scene::Scene>(scene::loadScene(path, ov));
}

std::unique_ptr<scene::Scene> ViewSession::loadWithDefaults(const fs::path& path,
                                                            std::vector<std::string>& ov) const {
    std::unique_ptr<scene::Scene> parsed = loadWith(path, ov);
    // The viewer's default for `reference`: keep the capped pool and count the dropped
    // fragments instead of stopping (render's default is the error). Written as an
    // override, so the copied render command says it too.
    if (parsed->render.oit == "reference" &&
        !(parsed->render.oitProperties.is_object() &&
          parsed->render.oitProperties.contains("pool_overflow"))) {
        addOverride(ov, "render.oit.pool_overflow=drop");
        parsed = loadWith(path, ov);
    }
    return parsed;
}

// Later values of a key replace earlier ones; a key replaces the keys below it.
void ViewSession::addOverride(std::vector<std::string>& list, const std::string& kv) const {
    VEIL_CHECK(kv.find('=') != std::string::npos,
               "override '{}': expected key=value, for example render.exposure=2", printable(kv));
    const std::string key = keyOf(kv);
    std::erase_if(list, [&](const std::string& o) {
        const std::string k = keyOf(o);
        return k == key || startsWith(k, key + ".");
    });
    list.push_back(kv);
}

void ViewSession::rebuild(const fs::path& path, std::vector<std::string>& overrides) {
    std::unique_ptr<scene::Scene> next = loadWithDefaults(path, overrides);
    int w = width_ > 0 ? width_ : next->render.width;
    int h = height_ > 0 ? height_ : next->render.height;
    std::string cameraName = cameraName_;
    if (cameraName.empty() || std::none_of(next->cameras.begin(), next->cameras.end(),
                                           [&](const auto& c) { return c.name == cameraName; }))
        cameraName = next->camera(next->render.camera).name;
    frame::RendererOptions options{w, h, cameraName};
    options.reuseShadowMaps = reuseShadowMaps_; // a new renderer draws its maps afresh
    auto renderer = std::make_unique<frame::Renderer>(*next, context_, options);
    // The debug views offer every frame resource, fog.radiance too: keep the per-pixel fog
    // march that piecewise fog (`reference`) would skip.
    renderer->keepFogRadiance(true);
    nlohmann::json doc;
    if (lowerExtension(path.string()) == ".json") {
        std::ifstream in(path, std::ios::binary);
        std::stringstream text;
        text << in.rdbuf();
        doc = scene::parseJsonText(text.str(), path.string()); // it parsed above
    }
    // Replace only now: a failure above keeps the current scene and renderer.
    const bool sameScene = path == scenePath_ && scene_;
    sourceDoc_ = std::move(doc);
    renderer_ = std::move(renderer);
    scene_ = std::move(next);
    width_ = w;
    height_ = h;
    cameraName_ = cameraName;
    adoptCamera(!sameScene);
    frameFailed_ = false;
    ++rebuilds_;
}

void ViewSession::adoptCamera(bool resetOrbit) {
    const scene::Camera sceneCamera = scene_->camera(cameraName_);
    if (resetOrbit) {
        orbited_ = false;
        orbit_.from(sceneCamera);
    }
    camera_ = sceneCamera;
    if (orbited_) orbit_.apply(camera_);
    renderer_->setCamera(camera_);
}

bool ViewSession::record(const std::string& error) {
    lastError_ = error;
    errors_.push_back(error);
    log::error("{}", error);
    return false;
}

bool ViewSession::succeed(const std::string& what) {
    ++version_;
    lastError_.clear();
    status_ = what;
    return true;
}

void ViewSession::fail(const std::string& what) { record(what); }

bool ViewSession::set(const std::string& keyValue) {
    try {
        std::vector<std::string> next = overrides_;
        addOverride(next, keyValue);
        const std::string key = keyOf(keyValue);
        OverrideScope scope = classifyOverride(key);
        std::unique_ptr<scene::Scene> parsed = loadWithDefaults(scenePath_, next);
        if (scope == OverrideScope::Live && startsWith(key, "volumes.")) {
            const std::size_t i = std::stoul(splitKey(key)[1]);
            // Homogeneous fog is summed into global values when the fog pass is built.
            if (i >= scene_->volumes.size() || scene_->volumes[i].procedural == "homogeneous")
                scope = OverrideScope::Renderer;
        }
        if (scene_->volumes.size() != parsed->volumes.size() ||
            scene_->lights.size() != parsed->lights.size() ||
            scene_->materials.size() != parsed->materials.size() ||
            scene_->cameras.size() != parsed->cameras.size())
            scope = OverrideScope::Renderer;
        switch (scope) {
        case OverrideScope::Camera:
            scene_->cameras = parsed->cameras;
            adoptCamera(false);
            break;
        case OverrideScope::Live: {
            // The scene's values declared live (scene/scene_values.cpp), the edited one with
            // them: those not edited are equal in both scenes.
            scene::Scene& s = *scene_;
            scene::copyLiveValues(scene::renderValueDecls(), parsed->render, s.render);
            for (std::size_t i = 0; i < s.lights.size(); ++i) {
                scene::copyLiveValues(scene::lightValueDecls(), parsed->lights[i], s.lights[i]);
                s.lights[i].direction = parsed->lights[i].direction; // the aim (kLightAimEdit)
            }
            for (std::size_t i = 0; i < s.materials.size(); ++i)
                scene::copyLiveValues(scene::materialValueDecls(), parsed->materials[i],
                                      s.materials[i]);
            for (std::size_t i = 0; i < s.volumes.size(); ++i)
                scene::copyLiveValues(scene::volumeValueDecls(), parsed->volumes[i], s.volumes[i]);
            const scene::EditEffect effect = overrideEditEffect(key);
            if (effect == scene::EditEffect::Relight) {
                renderer_->sceneValuesChanged(); // the shadow maps too
                ++valueChanges_;
            }
            if (effect != scene::EditEffect::Live) renderer_->invalidateShadowMaps();
            break;
        }
        case OverrideScope::Oit:
            renderer_->setOitTechnique(parsed->render.oit, parsed->render.oitProperties,
                                       parsed->render.oitWhere);
            scene_->render.oit = parsed->render.oit;
            scene_->render.oitProperties = parsed->render.oitProperties;
            scene_->render.oitWhere = parsed->render.oitWhere;
            break;
        case OverrideScope::Size:
            renderer_->resize(parsed->render.width, parsed->render.height);
            scene_->render.width = parsed->render.width;
            scene_->render.height = parsed->render.height;
            width_ = parsed->render.width;
            height_ = parsed->render.height;
            break;
        case OverrideScope::Renderer:
            rebuild(scenePath_, next);
            break;
        }
        overrides_ = std::move(next);
        frameFailed_ = false;
        return succeed("set " + keyValue);
    } catch (const Error& e) {
        return record(e.what());
    }
}

bool ViewSession::showFrame(int frame, const std::vector<volume::PreloadedGrid>& grids) {
    const std::string keyValue = fmt::format("time.frame={}", frame);
    try {
        std::vector<std::string> next = overrides_;
        addOverride(next, keyValue);
        const std::unique_ptr<scene::Scene> parsed = loadWithDefaults(scenePath_, next);
        std::vector<const volume::GridConversion*> converted;
        if (!sequence::replaceableBy(*scene_, *parsed, grids, context_.max3DTextureSize,
                                     converted)) {
            const volume::PreloadedGridScope preloaded(grids);
            return set(keyValue);
        }
        // Element by element: the fog pass keeps pointers to the volume entries.
        scene::Scene& s = *scene_;
        for (std::size_t i = 0; i < s.volumes.size(); ++i)
            s.volumes[i] = parsed->volumes[i];
        for (std::size_t i = 0; i < s.lights.size(); ++i)
            s.lights[i] = parsed->lights[i];
        for (std::size_t i = 0; i < s.cameras.size(); ++i)
            s.cameras[i] = parsed->cameras[i];
        const volume::PreloadedGridScope preloaded(grids); // a scattered-light cache's grids
        renderer_->replaceVolumes(converted, cameraName_);
        adoptCamera(false);
        overrides_ = std::move(next);
        frameFailed_ = false;
        ++rebuilds_; // the error view's reference follows the new frame
        ++framesReplaced_;
        return succeed("set " + keyValue);
    } catch (const Error& e) {
        return record(e.what());
    }
}

bool ViewSession::open(const fs::path& path) {
    try {
        VEIL_CHECK(fs::is_regular_file(path), "cannot open '{}': no such file", path.string());
        const std::string ext = lowerExtension(path.string());
        VEIL_CHECK(ext == ".json" || ext == ".vdb",
                   "cannot open '{}': the viewer opens scenes (.json) and OpenVDB files (.vdb)",
                   path.string());
        const std::string previousCamera = cameraName_;
        cameraName_.clear(); // the new scene's camera
        std::vector<std::string> list;
        try {
            rebuild(path, list);
        } catch (...) {
            cameraName_ = previousCamera;
            throw;
        }
        scenePath_ = path;
        overrides_ = std::move(list);
        return succeed("opened " + path.string());
    } catch (const Error& e) {
        return record(e.what());
    }
}

bool ViewSession::selectOit(const std::string& name) {
    return set(fmt::format("render.oit={{\"type\":\"{}\"}}", name));
}

bool ViewSession::selectShadows(const std::string& name) {
    return set(fmt::format("render.shadows={{\"type\":\"{}\"}}", name));
}

bool ViewSession::selectCamera(const std::string& name) {
    try {
        scene_->camera(name); // throws for an unknown name
        cameraName_ = name;
        adoptCamera(true);
        return succeed("camera " + name);
    } catch (const Error& e) {
        return record(e.what());
    }
}

bool ViewSession::resize(int width, int height) {
    if (width == width_ && height == height_) return true;
    try {
        renderer_->resize(width, height);
        width_ = width;
        height_ = height;
        frameFailed_ = false;
        ++version_;
        return true;
    } catch (const Error& e) {
        return record(e.what());
    }
}

void ViewSession::setReuseShadowMaps(bool on) {
    reuseShadowMaps_ = on;
    renderer_->setReuseShadowMaps(on);
}

bool ViewSession::reloadShaders() {
    std::vector<std::string> failures;
    const int failed = renderer_->reloadShaders(&failures);
    if (failed == 0) return succeed("shaders reloaded");
    frameFailed_ = false;
    return record(fmt::format("{} program(s) kept their previous version: {}", failed,
                              failures.empty() ? std::string("see the log") : failures.front()));
}

void ViewSession::orbitBy(float dyaw, float dpitch, float zoom) {
    // A script's huge or non-finite steps leave a finite camera: non-finite ones are ignored,
    // angles wrap, the distance stays in [1e-4, Orbit::kMaxExtent].
    if (!std::isfinite(dyaw + dpitch + zoom) || zoom <= 0.0f) return;
    orbited_ = true;
    orbit_.yaw = float(std::remainder(double(orbit_.yaw) + dyaw, 2.0 * M_PI));
    orbit_.pitch = float(std::clamp(double(orbit_.pitch) + dpitch, -1.55, 1.55));
    orbit_.distance =
        float(std::clamp(double(orbit_.distance) * zoom, 1e-4, double(Orbit::kMaxExtent)));
    adoptCamera(false);
    ++version_;
}

void ViewSession::panBy(float dx, float dy) {
    if (!std::isfinite(dx + dy)) return; // as orbitBy
    orbited_ = true;
    orbit_.pan(dx, dy);
    adoptCamera(false);
    ++version_;
}

void ViewSession::resetCamera() {
    adoptCamera(true);
    status_ = "camera reset to " + cameraName_;
    ++version_;
}

std::vector<std::string> ViewSession::cameraOverrides() const {
    if (!orbited_) return {};
    std::size_t index = 0;
    for (std::size_t i = 0; i < scene_->cameras.size(); ++i)
        if (scene_->cameras[i].name == cameraName_) index = i;
    return {fmt::format("cameras.{}.position={}", index, exact(camera_.position)),
            fmt::format("cameras.{}.target={}", index, exact(camera_.target)),
            fmt::format("cameras.{}.up={}", index, exact(camera_.up))};
}

std::vector<std::string> ViewSession::renderArguments(const std::string& output) const {
    std::vector<std::string> a = {"render",   fs::absolute(scenePath_).string(),
                                  "-o",       output,
                                  "--width",  std::to_string(width_),
                                  "--height", std::to_string(height_),
                                  "--camera", cameraName_};
    std::vector<std::string> all = overrides_;
    for (const std::string& c : cameraOverrides())
        addOverride(all, c);
    for (const std::string& o : all) {
        a.push_back("--set");
        a.push_back(o);
    }
    return a;
}

std::string ViewSession::renderCommand(const std::string& output) const {
    std::string line = "veil";
    for (const std::string& a : renderArguments(output)) {
        line += ' ';
        line.append(shellQuote(a));
    }
    return line;
}

bool ViewSession::saveSceneAs(const fs::path& path) {
    try {
        VEIL_CHECK(lowerExtension(scenePath_.string()) == ".json",
                   "save scene as: the scene is a bare .vdb ('{}'); open a .json scene",
                   scenePath_.string());
        VEIL_CHECK(lowerExtension(path.string()) == ".json",
                   "save scene as '{}': must end in .json", path.string());
        checkOutputPath(path, "save scene as", {scenePath_});
        std::ifstream in(scenePath_, std::ios::binary);
        VEIL_CHECK(in.good(), "cannot read '{}'", scenePath_.string());
        std::stringstream text;
        text << in.rdbuf();
        nlohmann::json doc = scene::parseJsonText(text.str(), scenePath_.string());
        std::vector<std::string> all = overrides_;
        for (const std::string& c : cameraOverrides())
            addOverride(all, c);
        scene::applyOverrides(doc, all);
        // Files named relative to the scene stay found from the new file's folder.
        const fs::path base = fs::absolute(scenePath_).parent_path();
        auto absolutize = [&](nlohmann::json& holder, const char* key) {
            if (holder.is_object() && holder.contains(key) && holder[key].is_string()) {
                const fs::path p = holder[key].get<std::string>();
                if (p.is_relative()) holder[key] = (base / p).lexically_normal().string();
            }
        };
        if (doc.contains("volumes") && doc["volumes"].is_array())
            for (auto& v : doc["volumes"])
                absolutize(v, "path");
        if (doc.contains("objects") && doc["objects"].is_array())
            for (auto& o : doc["objects"])
                absolutize(o, "mesh");
        scene::loadScene(scenePath_, all); // the saved values parse (they rendered)
        writeTextFileAtomically(path, doc.dump(2) + "\n");
        return succeed("saved " + path.string());
    } catch (const Error& e) {
        return record(e.what());
    }
}

bool ViewSession::oitAvailable(const std::string& name) const {
    const oit::TechniqueInfo* t = oit::Registry::instance().find(name);
    return t && (!t->isAvailable || t->isAvailable(context_));
}

bool ViewSession::shadowsAvailable(const std::string& name) const {
    const shadows::TechniqueInfo* t = shadows::Registry::instance().find(name);
    return t && (!t->isAvailable || t->isAvailable(context_));
}

} // namespace veil::session
