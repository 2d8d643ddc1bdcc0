// `veil view --script` (docs/viewer.md) in a real GLFW window on a virtual X display (Xvfb):
// edits equal `veil render --set` of the same values, debug views carry the values
// `veil render --dump` writes for the same frame, errors (a bad file, a failing technique,
// a bad value) leave the viewer running with the error shown and the last good frame, and
// the copied render command reproduces the screenshot. Each comparison is bit for bit: the
// same driver runs the same shaders on the same values, so any difference is a real one.
#include "io/image_io.h"
#include "support/test_support.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

// A fog scene small enough for llvmpipe: a grid volume (so density edits take the live
// path), homogeneous haze, a shadowed spot light, an opaque box and a transparent pane.
const char* kScene = R"({
  "render": {"width": 96, "height": 64, "oit": "reference", "fog_steps": 48,
             "shadows": {"type": "moment", "size": 128}},
  "cameras": [{"name": "c", "position": [0, 1.5, 4], "target": [0, 0.4, 0], "fov_y": 50},
              {"name": "side", "position": [4, 1.2, 0.5], "target": [0, 0.4, 0]}],
  "lights": [{"name": "spot", "type": "spot", "position": [1, 4, 1], "target": [0, 0, 0],
              "intensity": 30, "outer_cone": 35}],
  "materials": {"m": {"base_color": 0.5}, "glass": {"base_color": 1, "alpha": 0.5,
                "transmission": [0.2, 0.7, 0.9]}},
  "objects": [{"shape": {"type": "box", "size": [1, 1, 1]}, "material": "m",
               "transform": {"translate": [0.8, 0.5, 0]}},
              {"shape": {"type": "plane", "size": [3, 3]}, "material": "m"},
              {"shape": {"type": "box", "size": [1.2, 1, 0.05]}, "material": "glass",
               "transform": {"translate": [-0.3, 0.6, 1.0]}}],
  "volumes": [{"name": "ball", "procedural": "sphere", "size": 1.2, "voxel_size": 0.05,
               "density_scale": 3, "transform": {"translate": [-0.6, 0.7, 0]}},
              {"name": "haze", "procedural": "homogeneous", "density_scale": 0.05}]
})";

fs::path folder(const std::string& name) {
    const fs::path d = outputDir() / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string q(const fs::path& p) {
    std::string s(1, '\'');
    s.append(p.string());
    s.push_back('\'');
    return s;
}

CommandResult view(const fs::path& scene, const fs::path& script, const std::string& extra = "") {
    return runCommand("xvfb-run -a -s '-screen 0 640x480x24' " + veilExe() + " view " + q(scene) +
                      " --script " + q(script) + " " + extra);
}

ImageF exr(const fs::path& p) { return io::readImage(p); }

void expectSame(const fs::path& a, const fs::path& b, int channels = 3) {
    const ImageF x = io::readImage(a), y = io::readImage(b);
    ASSERT_EQ(x.width, y.width) << a << " vs " << b;
    ASSERT_EQ(x.height, y.height) << a << " vs " << b;
    const ImageDiff d = compareImages(x, y, channels);
    EXPECT_EQ(d.maxAbs, 0.0) << a << " vs " << b << ": RMSE " << d.rmse;
}

} // namespace

// `extra`: options for both commands (the shadow technique).
void checkEditsEqualRenderSet(const std::string& name, const std::string& extra) {
    const fs::path d = folder("view-script-set-" + name);
    const fs::path scene = writeTextFile(d / "scene.json", kScene);
    // Live edits (no renderer rebuild): a light first, then a grid volume's values (each
    // followed by a frame, so stale light transmittance volumes would show), then exposure.
    const std::vector<std::string> sets = {
        "lights.0.intensity=45",    "lights.0.position=[-1,4,1.5]",   "volumes.0.density_scale=7",
        "volumes.0.anisotropy=0.6", "volumes.0.albedo=[0.9,0.5,0.3]", "render.exposure=1.7"};
    nlohmann::json script = nlohmann::json::array();
    for (const std::string& s : sets)
        script.push_back({{"set", s}});
    script.push_back({{"screenshot", (d / "viewed.png").string()}});
    script.push_back({{"screenshot", (d / "viewed.exr").string()}});
    writeTextFile(d / "script.json", script.dump());
    CommandResult r = view(scene, d / "script.json", extra);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::string setArgs = " " + extra;
    for (const std::string& s : sets)
        setArgs += " --set '" + s + "'";
    setArgs += " --set render.oit.pool_overflow=drop"; // the viewer's default, in its command
    r = runCommand(veilExe() + " render " + q(scene) + " -o " + q(d / "rendered.png") + setArgs);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = runCommand(veilExe() + " render " + q(scene) + " -o " + q(d / "rendered.exr") + setArgs);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectSame(d / "viewed.png", d / "rendered.png");
    expectSame(d / "viewed.exr", d / "rendered.exr", 4); // R, G, B, A
    // The edits did something: the unedited frame differs.
    r = runCommand(veilExe() + " render " + q(scene) + " -o " + q(d / "unedited.exr") + " " +
                   extra);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_GT(compareImages(exr(d / "viewed.exr"), exr(d / "unedited.exr")).maxAbs, 0.01);
}

TEST(ViewScriptTest, PropertyChangeEqualsRenderSet) {
    ASSERT_EQ(runCommand("command -v xvfb-run").exitCode, 0) << "scripts/install-deps.sh";
    // moment shadows hold the media's absorbance; opaque shadows leave the fog its own light
    // transmittance volumes, which the density edit must recompute.
    checkEditsEqualRenderSet("moment", "");
    checkEditsEqualRenderSet("opaque", "--set render.shadows.type=opaque");
}

TEST(ViewScriptTest, DebugViewsEqualTheDumpOfTheSameFrame) {
    const fs::path d = folder("view-script-debug");
    const fs::path scene = writeTextFile(d / "scene.json", kScene);
    const std::vector<std::pair<std::string, std::string>> views = {
        {"depth", "depth.exr"},
        {"hdr", "hdr.exr"},
        {"fog.radiance", "fog.radiance.exr"},
        {"shadow.depth", "shadow.depth.layer0.exr"},
        {"shadow.moments", "shadow.moments.layer0.exr"}};
    nlohmann::json script = nlohmann::json::array();
    for (const auto& [resource, file] : views) {
        script.push_back({{"view", resource}, {"layer", 0}});
        script.push_back({{"screenshot", (d / ("viewed-" + file)).string()}});
        script.push_back({{"screenshot", (d / ("viewed-" + resource + ".png")).string()}});
    }
    writeTextFile(d / "script.json", script.dump());
    CommandResult r = view(scene, d / "script.json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = runCommand(veilExe() + " render " + q(scene) + " -o " + q(d / "frame.exr") +
                   " --set render.oit.pool_overflow=drop --dump " + q(d / "dump"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const auto& [resource, file] : views) {
        SCOPED_TRACE(resource);
        const ImageF a = exr(d / ("viewed-" + file)), b = exr(d / "dump" / file);
        ASSERT_EQ(a.channels, b.channels);
        expectSame(d / ("viewed-" + file), d / "dump" / file, a.channels);
        // The shown image is not flat: the resource's range spreads over black..white.
        const ImageF png = io::readImage(d / ("viewed-" + resource + ".png"));
        float lo = 1.0f, hi = 0.0f;
        for (float v : png.pixels)
            lo = std::min(lo, v), hi = std::max(hi, v);
        EXPECT_GT(hi - lo, 0.5f) << resource << " shows a flat image";
    }
}

TEST(ViewScriptTest, ErrorsLeaveTheViewerRunningWithTheLastGoodFrame) {
    const fs::path d = folder("view-script-errors");
    const fs::path scene = writeTextFile(d / "scene.json", kScene);
    const fs::path bad = writeTextFile(d / "bad.json", R"({"render": {"width": "wide"}})");
    const nlohmann::json script = {
        {{"screenshot", (d / "before.png").string()}},
        {{"open", (d / "missing.json").string()}},
        {{"open", bad.string()}},
        {{"set", "render.oit.initial_nodes_per_pixel=-3"}},
        {{"oit", "moment-p4-16"}}, // needs fragment shader interlock: not on llvmpipe
        // A failing frame: the reference pool capped far below the frame's fragments.
        {{"set", "render.oit.pool_overflow=error"}},
        {{"set", "render.oit.max_pool_mib=0.001"}},
        {{"screenshot", (d / "after.png").string()}},
        {{"status", (d / "status.json").string()}},
        // The capped pool in the viewer's mode: fragments dropped and counted, no error.
        {{"set", "render.oit.pool_overflow=drop"}},
        {{"status", (d / "dropped.json").string()}}};
    writeTextFile(d / "script.json", script.dump());
    const CommandResult r = view(scene, d / "script.json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json st = readJson(d / "status.json");
    const std::string errors = st["errors"].dump();
    EXPECT_NE(errors.find("missing.json"), std::string::npos) << errors;
    EXPECT_NE(errors.find("bad.json"), std::string::npos) << errors;
    EXPECT_NE(errors.find("/render/width"), std::string::npos) << errors;
    EXPECT_NE(errors.find("initial_nodes_per_pixel"), std::string::npos) << errors;
    EXPECT_NE(errors.find("moment-p4-16"), std::string::npos) << errors;
    EXPECT_NE(errors.find("capped"), std::string::npos) << errors;
    EXPECT_TRUE(st["frame_failed"].get<bool>());
    EXPECT_EQ(st["oit"], "reference"); // what renders, not the unavailable choice
    EXPECT_EQ(st["scene"], scene.string());
    expectSame(d / "before.png", d / "after.png"); // the last good frame stays
    const nlohmann::json dropped = readJson(d / "dropped.json");
    EXPECT_FALSE(dropped["frame_failed"].get<bool>());
    EXPECT_GT(dropped["oit_stats"]["pool_dropped_fragments"].get<long long>(), 0) << dropped;
}

TEST(ViewScriptTest, CopiedRenderCommandReproducesTheScreenshot) {
    const fs::path d = folder("view-script-command");
    const fs::path scene = writeTextFile(d / "scene.json", kScene);
    const nlohmann::json script = {{{"camera", "side"}},
                                   {{"orbit", {0.37, 0.21}}, {"zoom", 0.83}},
                                   {{"pan", {0.05, -0.03}}},
                                   {{"oit", "phenomenological"}},
                                   {{"set", "render.oit.k1=0.5"}},
                                   {{"set", "volumes.1.density_scale=0.12"}},
                                   {{"set", "render.fog_resolution=2"}},
                                   {{"screenshot", (d / "viewed.png").string()}},
                                   {{"copy_command", (d / "command.json").string()},
                                    {"output", (d / "rendered.png").string()}},
                                   {{"save_scene", (d / "saved.json").string()}}};
    writeTextFile(d / "script.json", script.dump());
    CommandResult r = view(scene, d / "script.json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json cmd = readJson(d / "command.json");
    // The line as a user pastes it into a shell.
    const std::string line = cmd["line"].get<std::string>();
    ASSERT_EQ(line.rfind("veil render ", 0), 0u) << line;
    r = runCommand(veilExe() + line.substr(4));
    ASSERT_EQ(r.exitCode, 0) << line << "\n" << r.output;
    expectSame(d / "viewed.png", d / "rendered.png");
    // The saved scene renders the same view with its camera.
    r = runCommand(veilExe() + " render " + q(d / "saved.json") + " -o " + q(d / "saved.png") +
                   " --camera side --width 96 --height 64");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectSame(d / "viewed.png", d / "saved.png");
}

TEST(ViewScriptTest, BadScriptIsOneClearError) {
    const fs::path d = folder("view-script-bad");
    const fs::path scene = writeTextFile(d / "scene.json", kScene);
    writeTextFile(d / "script.json", R"([{"set": "render.exposure=2"}, {"zoom_in": 3}])");
    const CommandResult r = view(scene, d / "script.json");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("script.json: action 1: unknown action 'zoom_in'"), std::string::npos)
        << r.output;
}

namespace {

// Every pixel of the shown image: not one flat colour.
void expectNotFlat(const fs::path& png) {
    const ImageF img = io::readImage(png);
    float lo = 1.0f, hi = 0.0f;
    for (float v : img.pixels)
        lo = std::min(lo, v), hi = std::max(hi, v);
    EXPECT_GT(hi - lo, 0.5f) << png << " shows a flat image";
}

} // namespace

// A known depth complexity: an orthographic camera looking down on three full-screen planes
// and a fourth covering the left half (x < 0, a pixel boundary at 64 px): `reference` stores
// 4 fragments per pixel on the left, 3 on the right, exactly (each plane rasterizes once per
// pixel: shared triangle edges are not drawn twice).
TEST(ViewScriptTest, FragmentsPerPixelHeatMapCountsTheStackedPlanes) {
    const fs::path d = folder("view-script-heatmap");
    const fs::path scene = writeTextFile(d / "scene.json", R"({
      "render": {"width": 64, "height": 48, "oit": "reference"},
      "cameras": [{"name": "top", "type": "orthographic", "ortho_height": 2,
                   "position": [0, 5, 0], "target": [0, 0, 0], "up": [0, 0, -1]}],
      "materials": {"glass": {"base_color": [0.8, 0.6, 0.4], "alpha": 0.4}},
      "objects": [
        {"shape": {"type": "plane", "size": [10, 10]}, "material": "glass"},
        {"shape": {"type": "plane", "size": [10, 10]}, "material": "glass",
         "transform": {"translate": [0, 0.3, 0]}},
        {"shape": {"type": "plane", "size": [10, 10]}, "material": "glass",
         "transform": {"translate": [0, 0.6, 0]}},
        {"shape": {"type": "plane", "size": [5, 10]}, "material": "glass",
         "transform": {"translate": [-2.5, 0.9, 0]}}]
    })");
    const std::string resource = "oit.reference.fragments_per_pixel";
    const nlohmann::json script = {{{"view", resource}},
                                   {{"screenshot", (d / "viewed.exr").string()}},
                                   {{"screenshot", (d / "viewed.png").string()}},
                                   {{"status", (d / "status.json").string()}}};
    writeTextFile(d / "script.json", script.dump());
    CommandResult r = view(scene, d / "script.json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = runCommand(veilExe() + " render " + q(scene) + " -o " + q(d / "frame.exr") +
                   " --set render.oit.pool_overflow=drop --dump " + q(d / "dump"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectSame(d / "viewed.exr", d / "dump" / (resource + ".exr"), 1);
    const ImageF counts = exr(d / "viewed.exr");
    ASSERT_EQ(counts.channels, 1);
    ASSERT_EQ(counts.width, 64);
    int wrong = 0;
    for (int y = 0; y < counts.height; ++y)
        for (int x = 0; x < counts.width; ++x)
            wrong += counts.pixels[std::size_t(y) * counts.width + x] != (x < 32 ? 4.0f : 3.0f);
    EXPECT_EQ(wrong, 0) << "pixels whose count is not 4 (left half) or 3 (right half)";
    // Shown as a heat map of [0, max]: the legend's maximum is the deepest pixel's count.
    const nlohmann::json st = readJson(d / "status.json");
    EXPECT_EQ(st["debug_range"], nlohmann::json::array({0.0, 4.0})) << st;
    const ImageF png = io::readImage(d / "viewed.png");
    // Left: the ramp's top (white); right: 3/4 of it (orange-yellow, little blue).
    EXPECT_GT(png.pixels[(10 * png.width + 5) * png.channels + 2], 0.9f);
    EXPECT_LT(png.pixels[(10 * png.width + 50) * png.channels + 2], 0.3f);
}

// Each technique's accumulation targets are frame resources: listed, dumped, and shown by
// the viewer with the values of the dump of the same frame.
TEST(ViewScriptTest, AccumulationTargetViewsEqualTheDump) {
    const fs::path d = folder("view-script-targets");
    const fs::path scene = writeTextFile(d / "scene.json", kScene);
    const std::vector<std::pair<std::string, std::vector<std::string>>> techniques = {
        {"wboit", {"oit.wboit.accum", "oit.wboit.revealage"}},
        {"moment-p6",
         {"oit.moment-p6.moments0", "oit.moment-p6.moments1", "oit.moment-p6.moments2",
          "oit.moment-p6.accum"}},
        {"phenomenological",
         {"oit.phenomenological.a", "oit.phenomenological.beta_d", "oit.phenomenological.delta"}}};
    nlohmann::json script = nlohmann::json::array();
    for (const auto& [oit, targets] : techniques) {
        script.push_back({{"oit", oit}});
        for (const std::string& t : targets) {
            script.push_back({{"view", t}});
            script.push_back({{"screenshot", (d / (t + ".exr")).string()}});
            script.push_back({{"screenshot", (d / (t + ".png")).string()}});
        }
    }
    script.push_back({{"status", (d / "status.json").string()}});
    writeTextFile(d / "script.json", script.dump());
    CommandResult r = view(scene, d / "script.json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(readJson(d / "status.json")["errors"].empty()) << r.output;
    for (const auto& [oit, targets] : techniques) {
        const fs::path dump = d / ("dump-" + oit);
        r = runCommand(veilExe() + " render " + q(scene) + " -o " + q(d / (oit + ".exr")) +
                       " --set 'render.oit={\"type\":\"" + oit + "\"}' --dump " + q(dump));
        ASSERT_EQ(r.exitCode, 0) << r.output;
        for (const std::string& t : targets) {
            SCOPED_TRACE(t);
            ASSERT_TRUE(fs::exists(dump / (t + ".exr"))) << "not dumped";
            const ImageF a = exr(d / (t + ".exr"));
            ASSERT_EQ(a.channels, exr(dump / (t + ".exr")).channels);
            expectSame(d / (t + ".exr"), dump / (t + ".exr"), a.channels);
            expectNotFlat(d / (t + ".png"));
        }
    }
}

// The live error against `reference`: zero where the technique is reference; for wboit
// exactly |wboit - reference| of the two `veil render` frames' linear radiance, with its RMSE.
TEST(ViewScriptTest, ErrorViewAgainstReference) {
    const fs::path d = folder("view-script-error");
    const fs::path scene = writeTextFile(d / "scene.json", kScene);
    const nlohmann::json script = {{{"view", "error vs reference"}},
                                   {{"screenshot", (d / "error-reference.exr").string()}},
                                   {{"status", (d / "status-reference.json").string()}},
                                   {{"oit", "wboit"}},
                                   {{"screenshot", (d / "error-wboit.exr").string()}},
                                   {{"screenshot", (d / "error-wboit.png").string()}},
                                   {{"status", (d / "status-wboit.json").string()}}};
    writeTextFile(d / "script.json", script.dump());
    CommandResult r = view(scene, d / "script.json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json same = readJson(d / "status-reference.json");
    EXPECT_EQ(same["error_vs_reference"]["rmse"], 0.0) << same;
    EXPECT_EQ(same["error_vs_reference"]["max_abs"], 0.0) << same;
    const ImageF zero = exr(d / "error-reference.exr");
    ASSERT_EQ(zero.channels, 3);
    EXPECT_EQ(*std::max_element(zero.pixels.begin(), zero.pixels.end()), 0.0f);

    r = runCommand(veilExe() + " render " + q(scene) + " -o " + q(d / "reference.exr") +
                   " --set render.oit.pool_overflow=drop");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = runCommand(veilExe() + " render " + q(scene) + " -o " + q(d / "wboit.exr") +
                   " --set 'render.oit={\"type\":\"wboit\"}'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const ImageF w = exr(d / "wboit.exr"), ref = exr(d / "reference.exr"),
                 e = exr(d / "error-wboit.exr");
    ASSERT_EQ(e.width, w.width);
    ASSERT_EQ(e.height, w.height);
    ASSERT_EQ(e.channels, 3);
    int differ = 0;
    double sum = 0.0, largest = 0.0;
    for (int p = 0; p < w.width * w.height; ++p)
        for (int c = 0; c < 3; ++c) {
            const float expected =
                std::fabs(w.pixels[p * w.channels + c] - ref.pixels[p * ref.channels + c]);
            differ += e.pixels[p * 3 + c] != expected;
            sum += double(expected) * expected;
            largest = std::max(largest, double(expected));
        }
    EXPECT_EQ(differ, 0) << "error texels not |wboit - reference| of the rendered frames";
    EXPECT_GT(largest, 1e-3) << "wboit should differ from the exact composite";
    const nlohmann::json st = readJson(d / "status-wboit.json");
    const double rmse = std::sqrt(sum / (3.0 * w.width * w.height));
    EXPECT_NEAR(st["error_vs_reference"]["rmse"].get<double>(), rmse, 1e-9 * rmse) << st;
    EXPECT_EQ(st["error_vs_reference"]["max_abs"].get<double>(), largest) << st;
    expectNotFlat(d / "error-wboit.png");
}

// Progressive refinement (docs/viewer.md "Slow drivers"): datasets/scenes/fog.json refined
// in 40 px tiles (4 x 3 on 150 x 97, the last column and row partial) with the fog marched at
// 1/4 resolution (its joint-bilateral upsampling reads fog texels across tile edges: without
// the refinement's margin the tile edges differ, by up to 0.033) equals the frame in one
// piece bit for bit, for the scene's `reference` (fog in segments between the surfaces) and
// for `wboit` (fog through the per-pixel emission), and equals `veil render` of the same
// values. Exact, not within a tolerance: each pixel runs the same shaders on the same values
// in both (its march jitter hashes its own coordinate), so any difference is a real one.
TEST(ViewScriptTest, TiledRefinementEqualsTheWholeFrame) {
    const fs::path d = folder("view-script-refine");
    const fs::path scene = sourceDir() / "datasets/scenes/fog.json";
    const auto shot = [&](const std::string& name) {
        return nlohmann::json{{"screenshot", (d / name).string()}};
    };
    const nlohmann::json script = {shot("whole-reference.exr"),
                                   {{"refine_tile_px", 40}},
                                   shot("tiled-reference.exr"),
                                   shot("tiled-reference.png"),
                                   {{"status", (d / "status-reference.json").string()}},
                                   {{"oit", "wboit"}},
                                   shot("tiled-wboit.exr"),
                                   shot("tiled-wboit.png"),
                                   {{"status", (d / "status-wboit.json").string()}},
                                   {{"view", "oit.wboit.accum"}},
                                   shot("accum-refine-on.exr"),
                                   {{"view", "frame"}},
                                   {{"refine_tile_px", 0}},
                                   shot("whole-wboit.exr"),
                                   {{"view", "oit.wboit.accum"}},
                                   shot("accum-refine-off.exr")};
    writeTextFile(d / "script.json", script.dump());
    const std::string options = " --width 150 --height 97 --set render.shadows.size=256 --set "
                                "render.fog_resolution=4";
    CommandResult r = view(scene, d / "script.json", options);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const std::string oit : {"reference", "wboit"}) {
        SCOPED_TRACE(oit);
        const nlohmann::json st = readJson(d / ("status-" + oit + ".json"));
        EXPECT_TRUE(st["errors"].empty()) << st;
        EXPECT_EQ(st["oit"], oit);
        // The screenshot was of a refined frame: 12 tiles, all done.
        EXPECT_EQ(st["refinement"]["tiles"], 12) << st;
        EXPECT_EQ(st["refinement"]["complete"], true) << st;
        expectSame(d / ("tiled-" + oit + ".exr"), d / ("whole-" + oit + ".exr"), 4);
        expectNotFlat(d / ("tiled-" + oit + ".png"));
    }
    EXPECT_EQ(readJson(d / "status-wboit.json")["refinement"]["completed"], 2);
    // Under a debug view the frame renders in one piece (a refinement leaves the OIT targets
    // holding its last tile's work): the accumulation target is the whole frame's.
    expectSame(d / "accum-refine-on.exr", d / "accum-refine-off.exr", 4);
    // Against the one-shot `veil render` of the same values (the viewer's reference default
    // pool_overflow=drop included).
    r = runCommand(veilExe() + " render " + q(scene) + " -o " + q(d / "rendered.exr") + options +
                   " --set render.oit.pool_overflow=drop");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectSame(d / "tiled-reference.exr", d / "rendered.exr", 4);
    // The two techniques differ (the comparison above is not of one image with itself).
    EXPECT_GT(compareImages(exr(d / "tiled-reference.exr"), exr(d / "tiled-wboit.exr")).maxAbs,
              1e-3);
}

// With refinement on, no UI frame runs the per-pixel passes over more than one tile: the
// session counts, per displayed frame, the tiles refined and the pixels the per-pixel passes
// covered (a tile and its margin), so the check is on work done, not on time. In one piece
// the frame would be 96 x 64 = 6144 pixels in one UI frame; in 16 px tiles (6 x 4) at most
// (16 + 2 margin)^2. The refinement spans one UI frame for its per-frame passes plus one per
// tile, and a camera move during it (a script action waits for it, so the orbit comes after
// it completed) refines again from the start.
TEST(ViewScriptTest, EachUiFrameRefinesAtMostOneTile) {
    const fs::path d = folder("view-script-refine-frames");
    const fs::path scene = writeTextFile(d / "scene.json", kScene);
    const nlohmann::json script = {{{"refine_tile_px", 16}},
                                   {{"status", (d / "status.json").string()}},
                                   {{"orbit", {0.2, 0.05}}},
                                   {{"status", (d / "status-orbit.json").string()}},
                                   {{"screenshot", (d / "orbit.png").string()}}};
    writeTextFile(d / "script.json", script.dump());
    CommandResult r = view(scene, d / "script.json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const char* name : {"status.json", "status-orbit.json"}) {
        SCOPED_TRACE(name);
        const nlohmann::json st = readJson(d / name);
        const nlohmann::json& f = st["refinement"];
        EXPECT_TRUE(st["errors"].empty()) << st;
        EXPECT_EQ(f["tile_px"], 16);
        EXPECT_EQ(f["tiles"], 24) << f;
        EXPECT_EQ(f["complete"], true) << f;
        EXPECT_EQ(f["max_tiles_per_ui_frame"], 1) << f;
        // Plus, when the refinement drew the shadow maps (the first; the orbit's keeps them),
        // one UI frame per shadow band and one for the passes after them.
        const int shadowSteps = f["shadow_steps"].get<int>();
        EXPECT_EQ(shadowSteps, std::string(name) == "status.json" ? 4 : 0) << f;
        EXPECT_EQ(f["ui_frames"], 24 + 1 + shadowSteps + (shadowSteps > 0 ? 1 : 0)) << f;
        EXPECT_LE(f["max_per_frame_steps_per_ui_frame"], 1) << f;
        const long long side = 16 + 2 * f["margin_px"].get<long long>();
        EXPECT_LE(f["max_pixels_per_ui_frame"].get<long long>(), side * side) << f;
        EXPECT_LT(side * side, 96 * 64) << "the bound would not tell a tile from the frame";
    }
    EXPECT_EQ(readJson(d / "status.json")["refinement"]["completed"], 1);
    EXPECT_EQ(readJson(d / "status-orbit.json")["refinement"]["completed"], 2);
    expectNotFlat(d / "orbit.png");
}

// Shadow map reuse in the session (view.reuse_shadow_maps, on by default; docs/viewer.md
// "Slow drivers"): camera orbits keep the `moment` maps (the status JSON's shadow_maps counts
// one drawing), a live material edit and a live light edit each redraw them (the session's
// invalidation), and the frame after the edits equals `veil render` of the copied command bit
// for bit (stale maps would differ: the light moved). With --reuse-shadow-maps false every
// frame draws them.
TEST(ViewScriptTest, ShadowMapsKeptAcrossOrbitsRedrawnAfterEdits) {
    const fs::path d = folder("view-script-shadow-reuse");
    const fs::path scene = writeTextFile(d / "scene.json", kScene);
    const auto status = [&](const std::string& name) {
        return nlohmann::json{{"status", (d / name).string()}};
    };
    const nlohmann::json script = {{{"frames", 1}},
                                   {{"orbit", {0.3, 0.1}}},
                                   {{"frames", 1}},
                                   {{"orbit", {0.2, 0.0}}},
                                   {{"screenshot", (d / "orbit.png").string()}},
                                   status("orbit.json"),
                                   {{"set", "materials.glass.base_color=0.3"}},
                                   {{"frames", 1}},
                                   status("material.json"),
                                   {{"set", "lights.0.position=[-1,4,1.5]"}},
                                   {{"screenshot", (d / "edited.png").string()}},
                                   status("light.json"),
                                   {{"copy_command", (d / "command.json").string()},
                                    {"output", (d / "rendered.png").string()}}};
    writeTextFile(d / "script.json", script.dump());
    CommandResult r = view(scene, d / "script.json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json orbit = readJson(d / "orbit.json"),
                         material = readJson(d / "material.json"),
                         light = readJson(d / "light.json");
    EXPECT_TRUE(light["errors"].empty()) << light;
    EXPECT_EQ(orbit["shadow_maps"]["reuse"], true) << orbit;
    EXPECT_EQ(orbit["shadow_maps"]["renders"], 1) << "an orbit redrew the maps: " << orbit;
    EXPECT_GE(orbit["shadow_maps"]["reuses"].get<int>(), 2) << orbit;
    EXPECT_EQ(material["shadow_maps"]["renders"], 2) << "a material edit kept them: " << material;
    EXPECT_EQ(light["shadow_maps"]["renders"], 3) << "a light edit kept them: " << light;
    const std::string line = readJson(d / "command.json")["line"].get<std::string>();
    ASSERT_EQ(line.rfind("veil render ", 0), 0u) << line;
    r = runCommand(veilExe() + line.substr(4));
    ASSERT_EQ(r.exitCode, 0) << line << "\n" << r.output;
    expectSame(d / "edited.png", d / "rendered.png");

    // Off by the option, and by the script action (view.reuse_shadow_maps both).
    nlohmann::json actionOff = nlohmann::json::array({{{"reuse_shadow_maps", false}}});
    for (const auto& a : script)
        actionOff.push_back(a);
    writeTextFile(d / "script-off.json", actionOff.dump());
    for (const auto& [file, option] :
         {std::pair<std::string, std::string>{"script.json", "--reuse-shadow-maps false"},
          {"script-off.json", ""}}) {
        SCOPED_TRACE(file);
        r = view(scene, d / file, option);
        ASSERT_EQ(r.exitCode, 0) << r.output;
        const nlohmann::json off = readJson(d / "orbit.json");
        EXPECT_EQ(off["shadow_maps"]["reuse"], false) << off;
        EXPECT_EQ(off["shadow_maps"]["reuses"], 0) << off;
        EXPECT_GE(off["shadow_maps"]["renders"].get<int>(), 3) << off;
    }
}

} // namespace veil::test
