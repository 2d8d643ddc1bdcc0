// The viewer's timeline window (timeline_panel.h).
#include "viewer/ui/timeline_panel.h"

#include <imgui.h>

#include <fmt/format.h>

#include <algorithm>

namespace veil::ui {

std::string timelineSliderFormat(const scene::FrameRange& range) {
    std::string text = fmt::format("frame %d of {}-{}", range.first, range.last);
    if (range.step != 1) text += fmt::format(":{}", range.step);
    return text;
}

void drawTimeline(session::TimelinePlayer& player) {
    if (!player.animated()) return;
    const ImGuiIO& io = ImGui::GetIO();
    const float em = ImGui::GetFontSize();
    // Bottom left of the frame, beside the main panel (em * 30 wide at the left edge).
    const float left = em * 31.0f;
    ImGui::SetNextWindowPos(ImVec2(left, io.DisplaySize.y - em * 0.5f), ImGuiCond_FirstUseEver,
                            ImVec2(0.0f, 1.0f));
    ImGui::SetNextWindowSize(
        ImVec2(std::max(em * 20, std::min(em * 34, io.DisplaySize.x - left - em * 0.5f)), 0),
        ImGuiCond_FirstUseEver);
    if (!ImGui::Begin("Timeline")) {
        ImGui::End();
        return;
    }
    const scene::FrameRange& r = player.range();
    if (ImGui::Button("|<")) player.seek(r.first);
    ImGui::SameLine();
    if (ImGui::Button("<")) {
        player.play(false);
        player.step(-1);
    }
    ImGui::SameLine();
    if (ImGui::Button(player.playing() ? "Pause" : "Play")) player.play(!player.playing());
    ImGui::SameLine();
    if (ImGui::Button(">")) {
        player.play(false);
        player.step(1);
    }
    ImGui::SameLine();
    if (ImGui::Button(">|")) player.seek(r.last);
    ImGui::SameLine();
    bool loop = player.looping();
    if (ImGui::Checkbox("loop", &loop)) player.setLoop(loop);
    ImGui::SameLine();
    float fps = static_cast<float>(player.fps());
    ImGui::SetNextItemWidth(em * 5);
    if (ImGui::DragFloat("fps", &fps, 0.25f, 0.1f, 1000.0f, "%.1f")) player.setFps(fps);
    int frame = player.target();
    ImGui::SetNextItemWidth(-1);
    const std::string format = timelineSliderFormat(r);
    if (ImGui::SliderInt("##frame", &frame, r.first, r.last, format.c_str())) {
        player.play(false);
        player.seek(r.first + (frame - r.first) / r.step * r.step);
    }
    ImGui::TextUnformatted(player.status().c_str());
    if (const session::FrameCache* cache = player.cache())
        ImGui::TextDisabled("%s", fmt::format("cache: {} frames, {:.1f} MiB", cache->frames(),
                                              cache->bytes() / 1048576.0)
                                      .c_str());
    ImGui::End();
}

} // namespace veil::ui
