// The viewer's timeline window (ImGui) over a session::TimelinePlayer: play / pause, step back
// and forward, first / last frame, a slider to scrub, loop, fps, and what is shown (the frame,
// "loading" while the frame aimed at streams in, or the error of a frame that failed) with
// the stream cache's frames and memory. Drawn only for an animated scene.
#pragma once

#include "viewer/session/timeline_player.h"

namespace veil::ui {

void drawTimeline(session::TimelinePlayer& player);

} // namespace veil::ui
