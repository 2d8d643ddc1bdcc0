// veil-bench --light-drag: the viewer's frames while a light is dragged, with the progressive
// bake of the scattered-light cache (render.fog_scattered_light_budget_ms and _frame_ms, as
// the viewer gives them: fog/scattered_light_cache.h progressiveBakeMs), and optionally
// (--converge) the cache's and the frame's error against the converged ones over the time
// after the drag stops (bench/README.md, bench/sets/scattered-light-interactive.json).
#pragma once

#include <string>
#include <vector>

namespace veil::bench {

struct LightDragOptions {
    std::string scene, oit, json;
    std::vector<std::string> overrides;
    int width = 1920, height = 1080, frames = 60, warmup = 0;
    double degreesPerFrame = 0.5; // the first light's turn per frame about the camera's up
    bool converge = false;        // then the error over the time after the drag
    std::vector<double> times{0.1, 0.25, 0.5, 1.0, 2.0}; // seconds after the drag stops
};

// Runs the drag (and the convergence), prints the JSON and writes it to options.json; the
// exit status. Throws veil::Error for a scene without the GPU-baked cache or without a light.
int lightDragBench(const LightDragOptions& options);

} // namespace veil::bench
