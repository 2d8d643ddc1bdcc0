// Private to src/scene: the JSON scene parser with the source name used in its messages.
#pragma once

#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace veil::scene::detail {

// Like parseScene; errors read "<source>: <json-pointer>: <problem>".
Scene parseSceneDocument(const nlohmann::json& doc, const std::filesystem::path& baseDir,
                         const std::string& source);

} // namespace veil::scene::detail
