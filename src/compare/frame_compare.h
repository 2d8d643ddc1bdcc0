// A rendered frame against what `veil render --compare-to X` names (compare/target.h): another
// OIT or shadow technique on the same frame, a stored image, the fog's CPU reference or the
// path tracer, with the error between them.
#pragma once

#include "compare/compare.h"
#include "compare/sweep.h"
#include "compare/target.h"

#include <string>

namespace veil::compare {

struct FrameComparison {
    ImageF reference; // what the target gives
    ImageF compared;  // what is compared with it: the frame, or for cpu its fog alone
    std::string note; // what was compared, when it is not the frame itself
    ImageError error;
};

struct FrameCompareRequest {
    std::string oit;    // the frame's OIT technique
    std::string camera; // as the frame was rendered (empty: the scene's)
    std::string output; // the frame's file, named in notes
    bool progress = false;
};

// `frame` (rendered from `scene` with `request.oit`) against `target` (not Kind::None). A
// technique or shadows:ID target is rendered by `render` (shadows at the frame's map size); cpu
// on a scene with surfaces renders the fog alone again and compares that (the note says so).
FrameComparison compareFrame(const CompareTarget& target, const scene::Scene& scene,
                             const capture::RenderedFrame& frame,
                             const FrameCompareRequest& request, const FrameRender& render);

} // namespace veil::compare
