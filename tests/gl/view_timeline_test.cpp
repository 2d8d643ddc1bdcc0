// The viewer's timeline (`veil view --script` with time actions, session/timeline_player.h)
// in a real window on Xvfb: scrubbing to a frame and looping past the last frame show images
// equal, bit for bit, to `veil render --frame N` of the same scene; a missing middle frame is
// an error the viewer shows (status) while it keeps the last frame and goes on to the next.
// The frames after the first replace only the volumes' data, camera and lights in the
// viewer's renderer (ViewSession::showFrame), with the same images.
#include "io/image_io.h"
#include "support/test_support.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path fireFrame(int n) {
    return dataDir() / "vdb-embergen-fire-seq" / fmt::format("embergen_fire_a_{}.vdb", n);
}

// 64x64 fire under a 4-frame turntable: the camera and the grid change every frame.
std::string fireScene(const std::string& pattern) {
    const nlohmann::json doc = {
        {"render", {{"width", 64}, {"height", 64}, {"fog_steps", 48}, {"shadows", "opaque"}}},
        {"time", {{"fps", 24}}},
        {"cameras",
         {{{"position", {0, -62, -98}},
           {"target", {0, 0, -112}},
           {"up", {0, 0, 1}},
           {"fov_y", 40},
           {"near", 1},
           {"far", 400},
           {"turntable", {{"frames", 4}, {"start_frame", 1}}}}}},
        {"lights",
         {{{"type", "directional"}, {"direction", {-0.4, 0.5, -0.75}}, {"shadows", false}}}},
        {"volumes",
         {{{"name", "fire"}, {"path", pattern}, {"grid", "flames"}, {"density_scale", 6.0}}}}};
    return doc.dump(2);
}

CommandResult view(const fs::path& scene, const fs::path& script) {
    return runCommand("xvfb-run -a -s '-screen 0 640x480x24' " + veilExe() + " view " +
                      shellQuote(scene) + " --script " + shellQuote(script));
}

// `veil render --frame N` (the scene's OIT is `blend`: the viewer adds no default of its own).
fs::path renderFrame(const fs::path& scene, int frame, const fs::path& out) {
    const CommandResult r = runCommand(veilExe() + " render " + shellQuote(scene) + " --frame " +
                                       std::to_string(frame) + " -o " + shellQuote(out));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return out;
}

bool same(const fs::path& a, const fs::path& b) {
    const ImageF x = io::readImage(a), y = io::readImage(b);
    return x.width == y.width && x.height == y.height && x.channels == y.channels &&
           std::memcmp(x.pixels.data(), y.pixels.data(), x.pixels.size() * sizeof(float)) == 0;
}

bool hasOverride(const nlohmann::json& status, const std::string& o) {
    for (const auto& x : status["overrides"])
        if (x == o) return true;
    return false;
}

} // namespace

TEST(ViewTimelineTest, ScrubAndLoopEqualRenderFrame) {
    ASSERT_EQ(runCommand("command -v xvfb-run").exitCode, 0) << "scripts/install-deps.sh";
    const fs::path d = freshOutputDir("view_timeline", "scrub");
    const fs::path scene = writeTextFile(
        d / "fire.json",
        fireScene((dataDir() / "vdb-embergen-fire-seq" / "embergen_fire_a_#.vdb").string()));
    // Scrub to 3, back to 1, then from 4 play with loop on: 4 -> 1 -> 2 -> 3 (one frame per
    // displayed frame in a script: the play action's, then the two waited).
    const nlohmann::json script = {{{"frame", 3}},
                                   {{"screenshot", (d / "v3.png").string()}},
                                   {{"frame", 1}},
                                   {{"screenshot", (d / "v1.png").string()}},
                                   {{"loop", true}},
                                   {{"frame", 4}},
                                   {{"play", true}},
                                   {{"frames", 2}},
                                   {{"play", false}},
                                   {{"screenshot", (d / "looped.png").string()}},
                                   {{"status", (d / "status.json").string()}}};
    const fs::path scriptPath = writeTextFile(d / "script.json", script.dump(1));
    const CommandResult r = view(scene, scriptPath);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const fs::path r1 = renderFrame(scene, 1, d / "r1.png");
    const fs::path r3 = renderFrame(scene, 3, d / "r3.png");
    EXPECT_TRUE(same(d / "v3.png", r3))
        << writeFailureImages("timeline_v3", io::readImage(d / "v3.png"), io::readImage(r3));
    EXPECT_TRUE(same(d / "v1.png", r1));
    EXPECT_FALSE(same(r1, r3)); // the frames differ (camera and fire)
    const nlohmann::json status = readJson(d / "status.json");
    EXPECT_TRUE(hasOverride(status, "time.frame=3")) << status.dump();
    // 3, 1, 4 and the played frames, each without a renderer built.
    EXPECT_GE(status["frames_replaced"].get<int>(), 4) << status.dump();
    // 1 (after the scrub) and 3 (after the loop) shown again from the frames held on the GPU.
    EXPECT_GE(status["volume_frames_reshown"].get<int>(), 2) << status.dump();
    EXPECT_TRUE(same(d / "looped.png", r3));
    EXPECT_TRUE(status["errors"].empty()) << status.dump();
}

TEST(ViewTimelineTest, MissingMiddleFrameIsShownAndTheViewerGoesOn) {
    const fs::path d = freshOutputDir("view_timeline", "missing");
    for (int f : {1, 3, 4})
        fs::copy_file(fireFrame(f), d / fmt::format("f_{}.vdb", f));
    const fs::path scene = writeTextFile(d / "fire.json", fireScene((d / "f_#.vdb").string()));
    const nlohmann::json script = {{{"frame", 1}},
                                   {{"screenshot", (d / "a.png").string()}},
                                   {{"frame", 2}},
                                   {{"status", (d / "failed.json").string()}},
                                   {{"screenshot", (d / "b.png").string()}},
                                   {{"frame", 3}},
                                   {{"screenshot", (d / "c.png").string()}},
                                   {{"status", (d / "after.json").string()}}};
    const CommandResult r = view(scene, writeTextFile(d / "script.json", script.dump(1)));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json failed = readJson(d / "failed.json");
    ASSERT_FALSE(failed["errors"].empty()) << failed.dump();
    EXPECT_NE(failed["last_error"].get<std::string>().find("f_2.vdb"), std::string::npos)
        << failed.dump();
    EXPECT_TRUE(same(d / "a.png", d / "b.png")); // the last frame stays shown
    EXPECT_TRUE(same(d / "c.png", renderFrame(scene, 3, d / "r3.png")));
    EXPECT_TRUE(hasOverride(readJson(d / "after.json"), "time.frame=3"));
}

} // namespace veil::test
