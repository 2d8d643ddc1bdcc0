// The progress line's notes (base/progress.h): a note made inside another shows and then
// gives the outer one back; the CPU fog reference notes its rows done (a percentage and the
// time left); a technique sweep names each tile with its technique and k/N.
#include "base/progress.h"
#include "compare/sweep.h"
#include "grid/density_grid.h"
#include "integrators/cpu_reference.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <set>
#include <thread>

namespace veil::test {

TEST(ProgressNoteTest, InnerNoteGivesTheOuterOneBack) {
    EXPECT_EQ(progressNoteText(), "");
    {
        ProgressNote outer("tile 2/5: shadows moment");
        outer.set(0.5);
        {
            ProgressNote inner("baking");
            EXPECT_EQ(progressNoteText(), "baking");
        }
        const std::string text = progressNoteText();
        EXPECT_EQ(text.rfind("tile 2/5: shadows moment, 50 %, about ", 0), 0u) << text;
    }
    EXPECT_EQ(progressNoteText(), "");
}

TEST(ProgressNoteTest, CpuFogReferenceShowsRowsDone) {
    const nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 8, "height": 8, "ambient": 0.5},
      "cameras": [{"type": "orthographic", "position": [0, 0, 5], "target": [0, 0, 0],
                   "ortho_height": 2, "near": 1, "far": 10}],
      "volumes": [{"procedural": "box", "size": [2.4, 2.4, 0.5], "voxel_size": 0.05,
                   "density_scale": 2}]})");
    const scene::Scene s = scene::parseScene(doc, outputDir());
    const volume::CpuFogReference ref(s, {volume::loadVolume(s.volumes[0])});
    std::atomic<bool> done{false};
    std::set<std::string> seen;
    std::thread poll([&] {
        while (!done) {
            const std::string t = progressNoteText();
            if (t.find(" %, about ") != std::string::npos && seen.size() < 64) seen.insert(t);
        }
    });
    ref.render(s.cameras[0], 16, 400, 256);
    done = true;
    poll.join();
    ASSERT_FALSE(seen.empty()) << "no note with a percentage while rendering";
    for (const std::string& t : seen)
        EXPECT_EQ(t.rfind("marching 16x400 pixels, 256 steps per ray, ", 0), 0u) << t;
    EXPECT_EQ(progressNoteText(), ""); // gone with the render
}

// A shadows sweep with a stand-in for the renderer: the note names each tile's technique
// and its place, "tile k/N", N the number of tiles rendered.
TEST(ProgressNoteTest, SweepNamesEachTile) {
    std::vector<std::string> notes, techniques;
    const compare::FrameRender render = [&](const scene::Scene&, const std::string& oit,
                                            const std::string& shadows, const nlohmann::json&) {
        notes.push_back(progressNoteText());
        techniques.push_back(shadows);
        capture::RenderedFrame f;
        f.oit = oit;
        f.shadows = shadows;
        f.hdr = ImageF(2, 2, 4);
        f.shadowProperties = {{"size", 256}};
        return f;
    };
    const compare::Sweep sweep = compare::runSweep(compare::SweepKind::Shadows, scene::Scene{},
                                                   "blend", gpu::ContextInfo{}, render, {});
    ASSERT_GE(notes.size(), 2u);
    EXPECT_EQ(techniques.front(), "reference");
    for (std::size_t i = 0; i < notes.size(); ++i)
        EXPECT_EQ(notes[i], "tile " + std::to_string(i + 1) + "/" + std::to_string(notes.size()) +
                                ": shadows " + techniques[i]);
    EXPECT_EQ(compare::sweepTileNote(compare::SweepKind::Oit, "wboit", 3, 9), "tile 3/9: wboit");
    EXPECT_EQ(progressNoteText(), "");
}

} // namespace veil::test
