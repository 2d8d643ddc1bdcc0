// Private to src/scene: parsing of the scene format's time keys (animation_json.cpp).
#pragma once

#include "scene/json_reader.h"
#include "scene/timeline.h"

#include <optional>
#include <string>
#include <vector>

namespace veil::scene::detail {

// The keys a camera's / a light's / a volume's object accepts beyond its values, and the
// time block's keys.
const std::vector<std::string>& cameraAnimationKeys();
const std::vector<std::string>& lightAnimationKeys();
const std::vector<std::string>& sequenceKeys();
const std::vector<std::string>& timeKeys();

// "keys", "interpolation", "turntable" of a camera (after its type and values are read).
void parseCameraAnimation(const Obj& o, const Camera& c, CameraAnimation& a);
// "keys", "interpolation" of a light (after its type is read).
void parseLightAnimation(const Obj& o, const Light& l, LightAnimation& a);
// The "time" block.
void parseTime(const Obj& o, TimeSettings& t);
// A volume's "path" with a frame pattern, "frames" and the sequence values: fills v.path (the
// pattern, made absolute) and `sequence`; false when the path has no pattern (the sequence
// keys are then refused).
bool parseVolumeSequence(const Obj& o, VolumeRef& v, std::optional<FileSequence>& sequence);

} // namespace veil::scene::detail
