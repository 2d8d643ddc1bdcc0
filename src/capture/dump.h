// `veil render --dump DIR`: every frame resource the renderer exposes, written after the
// frame: 2D colour and depth textures as float32 EXR, 3D textures as VTK ImageData (.vti),
// and DIR/manifest.json naming each file with its resource, size, GL format and units.
// Resources without a frame texture (inside a technique, e.g. oit.accumulation) are listed
// with "dumpable": false and the reason.
#pragma once

#include "capture/resource_image.h"
#include "frame/renderer.h"
#include "io/exr_writer.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace veil::capture {

// What a resource's values mean (manifest "units", the viewer's debug view).
std::string resourceUnits(const std::string& resource);

// A resource image as a float32 EXR with `strings` as header attributes (the files of
// dumpFrame, the viewer's EXR screenshot of a debug view).
io::ExrImage resourceExr(const ResourceImage& image,
                         std::vector<std::pair<std::string, std::string>> strings);

// Refuses, before any rendering, a DIR that exists and is not a folder, or a non-empty
// folder that is not an earlier dump (no manifest.json): a dump replaces DIR as a whole.
void checkDumpDirectory(const std::filesystem::path& dir);

// Writes the files and manifest.json into a hidden sibling folder (".<name>.dump-<pid>") and
// renames it to DIR only when everything is written, so DIR is either a complete dump or
// what it was before (a failed or interrupted dump removes the sibling; a killed one leaves
// the hidden sibling, never a DIR without manifest.json). An earlier dump in DIR is replaced.
// Returns the manifest.
nlohmann::json dumpFrame(const frame::Renderer& renderer, const std::filesystem::path& dir);

} // namespace veil::capture
