// The viewer's timeline window (ImGui) over a session::TimelinePlayer: play / pause, step back
// and forward, first / last frame, a slider to scrub (showing the range), loop, fps, and what is
// shown (the frame, "loading" while the frame aimed at streams in, or the error of a frame that
// failed) with the stream cache's frames and memory. Drawn only for an animated scene.
#pragma once

#include "viewer/session/timeline_player.h"

#include <string>

namespace veil::ui {

void drawTimeline(session::TimelinePlayer& player);

// The frame slider's text (an ImGui format for the frame number): the frame and the range it
// moves in, "frame %d of 1-240" (with its step: "frame %d of 1-240:2").
std::string timelineSliderFormat(const scene::FrameRange& range);

} // namespace veil::ui
