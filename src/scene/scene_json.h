// Private to src/scene: the JSON scene parser with the source name used in its messages.
#pragma once

#include "scene/scene.h"
#include "scene/timeline.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace veil::scene::detail {

// Like parseScene, without choosing a frame: the time keys go into `timeline` (a sequence
// volume's path is its pattern); errors read "<source>: <json-pointer>: <problem>".
Scene parseSceneDocument(const nlohmann::json& doc, const std::filesystem::path& baseDir,
                         const std::string& source, Timeline* timeline);

} // namespace veil::scene::detail
