// The fog's scattered-light cache (render.fog_scattered_light, src/fog/scattered_light_cache.h):
// its bake named on the progress line with an estimate, and booked in `veil render --report` as
// scattered_light_bake_ms, apart from the frame's passes.
#include "base/progress.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

// A slab 2 x 0.5 x 2 (about 17 x 5 x 17 texels at 2 voxels per texel), lit from above, its
// cache baked on the CPU with 256 paths per texel (a few tenths of a second).
const char* kCachedSlab = R"({
  "render": {"width": 16, "height": 16, "ambient": [0.1, 0.1, 0.1], "background": [0, 0, 0],
             "fog_steps": 64, "fog_scattered_light": true, "fog_scattered_light_samples": 256,
             "fog_scattered_light_cell": 2, "fog_scattered_light_bake": "cpu"},
  "cameras": [{"name": "c", "type": "orthographic", "position": [0, 4, 0.01],
               "target": [0, 0, 0], "ortho_height": 2, "near": 0.5, "far": 20}],
  "lights": [{"type": "directional", "direction": [0, -1, 0], "intensity": 1}],
  "volumes": [{"procedural": "box", "size": [2, 0.5, 2], "voxel_size": 0.0625,
               "density_scale": 4, "albedo": 0.9, "anisotropy": 0.3}]})";

} // namespace

// The note's text: what is done, the fraction and the time left estimated from it.
TEST(ScatteredLightCacheTest, ProgressNoteNamesTheWorkAndEstimates) {
    EXPECT_EQ(progressNoteText(), "");
    {
        ProgressNote note("baking scattered-light cache on the CPU: 1024 cells x 8 paths");
        EXPECT_EQ(progressNoteText(),
                  "baking scattered-light cache on the CPU: 1024 cells x 8 paths");
        note.set(0.25);
        const std::string text = progressNoteText();
        EXPECT_NE(text.find("1024 cells x 8 paths, 25 %, about "), std::string::npos) << text;
        EXPECT_NE(text.find(" s left"), std::string::npos) << text;
    }
    EXPECT_EQ(progressNoteText(), ""); // gone with the note
}

// `veil render --report`: the bake's time as scattered_light_bake_ms, not inside pass `fog`.
TEST(ScatteredLightCacheTest, ReportBooksTheBakeApartFromThePasses) {
    const fs::path d = outputDir() / "scattered_light_report";
    fs::create_directories(d);
    std::ofstream(d / "scene.json") << kCachedSlab;
    const CommandResult r =
        runCommand(veilExe() + " render '" + (d / "scene.json").string() + "' -o '" +
                   (d / "out.png").string() + "' --report '" + (d / "report.json").string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json report = nlohmann::json::parse(readTextFile(d / "report.json"));
    ASSERT_TRUE(report.contains("scattered_light_bake_ms")) << report.dump(1);
    const double bake = report["scattered_light_bake_ms"].get<double>();
    EXPECT_GT(bake, 0.0);
    double fog = -1.0;
    for (const auto& p : report["passes"])
        if (p["name"] == "fog") fog = p["ms"].get<double>();
    ASSERT_GE(fog, 0.0) << report["passes"].dump();
    // The march of 16 x 16 pixels costs far less than 1445 texels x 256 paths; the pass booked
    // the bake before.
    EXPECT_LT(fog, 0.5 * bake) << report["passes"].dump();

    // Without the cache there is no such field.
    nlohmann::json plain = nlohmann::json::parse(kCachedSlab);
    plain["render"]["fog_scattered_light"] = false;
    std::ofstream(d / "plain.json") << plain.dump();
    const CommandResult p = runCommand(veilExe() + " render '" + (d / "plain.json").string() +
                                       "' -o '" + (d / "plain.png").string() + "' --report '" +
                                       (d / "plain-report.json").string() + "'");
    ASSERT_EQ(p.exitCode, 0) << p.output;
    EXPECT_FALSE(nlohmann::json::parse(readTextFile(d / "plain-report.json"))
                     .contains("scattered_light_bake_ms"));
}

} // namespace veil::test
