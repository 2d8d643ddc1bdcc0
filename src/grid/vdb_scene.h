// `veil render file.vdb`: a bare OpenVDB density framed like vdb_view does, with a default
// camera, light and density scale, so a volume can be looked at without writing a scene.
#pragma once

#include "scene/scene.h"

#include <glm/glm.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace veil::vdb {

struct VdbScene {
    scene::Scene scene;
    std::string description; // which grid was used and the defaults chosen, for stdout
    std::string gridName;
    std::size_t gridIndex = 0;
};

// The scene for `vdb`: its grid `selector` (a name or an index, grid/grid_select.h; default
// the first float grid) as the only volume, with
//  - camera "vdb": 40 degree field of view on the grid's world bounding box (its active
//    voxels) from the direction (0.3, 0.35, 1), as near as keeps every corner of the box
//    inside 90% of the view's height and width, its projection centred (frameBox);
//  - a directional light from above-front-left (intensity 3), ambient 0.1;
//  - density_scale chosen so that the median optical depth of the camera's lines of sight
//    through the density is 1.5 (grid/optical_depth.h; 6 / (max density x largest world
//    extent) when no line meets density), whatever the grid's units; albedo 0.9;
//  - `description` states the values used after the overrides;
//  - render 512 x 512 unless overridden; `overrides` (--set) apply to this document.
// A camera for the box lo..hi seen along -towardEye (up +y) with a vertical field of fovY
// degrees on a square view: looking at `target` from `distance` along towardEye, every corner
// of the box projects inside the fraction `fill` of the view, the box's projection centred
// and touching that border on its wider axis. `nearest` and `farthest`: the corners' depths.
struct BoxFraming {
    glm::dvec3 target{0.0};
    double distance = 0.0, nearest = 0.0, farthest = 0.0;
};
BoxFraming frameBox(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& towardEye,
                    double fovY, double fill);

VdbScene sceneForVdb(const std::filesystem::path& vdb, const std::string& selector,
                     const std::vector<std::string>& overrides,
                     const scene::TechniqueChoice& choice = {});

} // namespace veil::vdb
