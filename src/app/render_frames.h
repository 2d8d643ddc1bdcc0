// `veil render --frames A-B[:S]` / `--frame N`: a frame range of an animated scene into
// numbered images (src/sequence does the work).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace veil::app {

struct RenderFramesArgs {
    std::string scene, output, report, camera, oit, shadows;
    int width = 0, height = 0, device = -1;
    bool glDebug = false, half = false, progress = false, resume = false;
    std::vector<std::string> overrides;
    std::string frames;       // "A-B[:S]"
    std::optional<int> frame; // --frame N
};

void runRenderFrames(const RenderFramesArgs& args);

} // namespace veil::app
