// `veil render --dump DIR`: every frame resource the renderer exposes, written after the
// frame: 2D colour and depth textures as float32 EXR, 3D textures as VTK ImageData (.vti),
// and DIR/manifest.json naming each file with its resource, size, GL format and units.
// Resources without a frame texture (inside a technique, e.g. oit.accumulation) are listed
// with "dumpable": false and the reason.
#pragma once

#include "frame/renderer.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace veil::capture {

// What a resource's values mean (manifest "units", the viewer's debug view).
std::string resourceUnits(const std::string& resource);

// Refuses a DIR that exists and is not a folder, before any rendering.
void checkDumpDirectory(const std::filesystem::path& dir);

// Writes the files and manifest.json (each atomically; the manifest last). Returns the
// manifest.
nlohmann::json dumpFrame(const frame::Renderer& renderer, const std::filesystem::path& dir);

} // namespace veil::capture
