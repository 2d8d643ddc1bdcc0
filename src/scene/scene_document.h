// The steps of scene::loadScene for callers that keep the scene's JSON document (the Python
// module's Scene, python/src/scene_bindings.cpp): read a scene file's JSON, apply `--set`
// overrides, parse, each with the messages loadScene gives.
#pragma once

#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace veil::scene {

// The file's JSON (comments allowed; only regular files up to 256 MiB).
nlohmann::json readSceneDocument(const std::filesystem::path& path);
// applyTechniqueChoice, then applyOverrides, with errors prefixed by `source`
// ("<source>: override '...': ...").
void applySceneOverrides(nlohmann::json& doc, const std::vector<std::string>& overrides,
                         const std::string& source, const TechniqueChoice& choice = {});
// parseScene with errors reading "<source>: <json-pointer>: <problem>".
Scene parseScene(const nlohmann::json& doc, const std::filesystem::path& baseDir,
                 const std::string& source);

} // namespace veil::scene
