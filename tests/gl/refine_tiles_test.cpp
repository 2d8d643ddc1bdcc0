// The refinement's tiles split to fit a time budget (frame::Renderer::refineStep's maxTilePx,
// session::ViewSession's view.refine_budget_ms; docs/viewer.md "Slow drivers"): however the steps
// halve the grid's tiles, the tiles cover every pixel exactly once and the refined frame equals
// the frame in one piece bit for bit; the session takes the smallest tile while it has no
// estimate, halves tiles under a budget no step can meet, and keeps whole tiles under a budget
// every step meets.
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "io/image_io.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "texel_bits.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <vector>

namespace veil::test {

namespace fs = std::filesystem;

class RefineTilesTest : public GlTest {};

// datasets/scenes/fog.json at 100 x 70 (not a multiple of the tiles: edge tiles are partial)
// in 48 px grid tiles (3 x 2), the fog at half resolution (so the margin matters), each step
// given another maxTilePx (0: the tile as it is; 7 and 13 are odd, 1 splits to single pixels
// only where a tile is 1 px). Every step's tile lies inside its grid tile, is at most maxTilePx
// on a side, and the tiles never overlap and cover the frame; the ldr frame is render()'s.
TEST_F(RefineTilesTest, SplitTilesCoverTheFrameOnceAndEqualOnePiece) {
    const scene::Scene s = scene::loadScene(
        sourceDir() / "datasets/scenes/fog.json",
        {"render.width=100", "render.height=70", "render.shadows.type=opaque",
         "render.shadows.size=128", "render.fog_resolution=2", "render.oit={\"type\":\"wboit\"}"});
    frame::Renderer whole(s, info());
    whole.render();
    const std::vector<std::uint8_t> expected = rgba8(whole.ldrTexture());

    frame::Renderer tiled(s, info());
    const int grid = 48;
    tiled.beginRefinement(grid);
    EXPECT_EQ(tiled.refinement().tiles, 6);
    const int sizes[] = {16, 0, 7, 32, 13, 0, 24, 48, 20};
    std::vector<int> covered(100 * 70, 0);
    bool done = false;
    int steps = 0, tileSteps = 0, smaller = 0;
    while (!done && steps < 2000) {
        const int maxPx = sizes[steps % std::size(sizes)];
        const int before = tiled.refinement().done;
        done = tiled.refineStep(maxPx);
        ++steps;
        if (tiled.refinement().done == before) continue; // a light slab
        ++tileSteps;
        const glm::ivec4 t = tiled.refinement().lastTile;
        SCOPED_TRACE(testing::Message() << "step " << steps << " tile " << t.x << "," << t.y
                                        << " - " << t.z << "," << t.w << " max " << maxPx);
        ASSERT_LT(t.x, t.z);
        ASSERT_LT(t.y, t.w);
        EXPECT_EQ(t.x / grid, (t.z - 1) / grid) << "a tile across grid tiles";
        EXPECT_EQ(t.y / grid, (t.w - 1) / grid) << "a tile across grid tiles";
        if (maxPx > 0) {
            EXPECT_LE(t.z - t.x, maxPx);
            EXPECT_LE(t.w - t.y, maxPx);
        }
        smaller += (t.z - t.x) * (t.w - t.y) < 48 * 22; // smaller than any grid tile
        for (int y = t.y; y < t.w; ++y)
            for (int x = t.x; x < t.z; ++x)
                ++covered[std::size_t(y) * 100 + std::size_t(x)];
    }
    VEIL_EXPECT_NO_GL_ERROR();
    ASSERT_TRUE(done);
    EXPECT_GT(smaller, 20) << "the sizes should have split most tiles";
    EXPECT_EQ(tiled.refinement().done, tileSteps);
    EXPECT_EQ(tiled.refinement().pixelsDone, tiled.refinement().pixels);
    EXPECT_EQ(std::count(covered.begin(), covered.end(), 1), 100 * 70)
        << "every pixel in exactly one tile";
    EXPECT_EQ(differing(rgba8(tiled.ldrTexture()), expected), 0u) << "bytes of the refined frame";
}

// The shadow maps drawn in bands during a refinement (pass::Pass::executeRows,
// frame::Renderer::kRefineShadowBandTexels): fog.json's `moment` shadows with 512^2 maps
// (rows per band 131072 / 512 = 256: two bands per banded pass). The first call only begins
// the frame; then each step runs one band (or an unbanded pass), in pass order; then one step
// the per-frame passes after them (AO, opaque); then the tiles; the frame equals render()'s bit
// for bit, and the maps count as drawn once.
TEST_F(RefineTilesTest, ShadowMapsDrawnInBandsOneBandPerStep) {
    const scene::Scene s =
        scene::loadScene(sourceDir() / "datasets/scenes/fog.json",
                         {"render.width=64", "render.height=48", "render.shadows.size=512",
                          "render.fog_resolution=2", "render.oit={\"type\":\"wboit\"}"});
    ASSERT_EQ(s.render.shadows, "moment");
    frame::Renderer whole(s, info());
    whole.render();
    const std::vector<std::uint8_t> expected = rgba8(whole.ldrTexture());

    frame::Renderer tiled(s, info());
    const std::uint64_t renders0 = tiled.shadowMapRenders();
    tiled.beginRefinement(32);
    using Step = frame::Renderer::Refinement::Step;
    std::vector<Step> steps;
    bool done = false;
    while (!done && steps.size() < 500) {
        done = tiled.refineStep();
        steps.push_back(tiled.refinement().lastStep);
    }
    VEIL_EXPECT_NO_GL_ERROR();
    ASSERT_TRUE(done);
    const auto count = [&](Step k) { return std::count(steps.begin(), steps.end(), k); };
    // moment's passes: depth, transparent, media, filter, each banded (quantize only at 16 bits).
    const int rows = frame::Renderer::kRefineShadowBandTexels / 512;
    ASSERT_EQ(rows, 256);
    EXPECT_EQ(count(Step::ShadowBand), 4 * (512 / rows));
    EXPECT_EQ(tiled.refinement().shadowSteps, 4 * (512 / rows));
    EXPECT_EQ(count(Step::PerFrame), 1);
    EXPECT_EQ(count(Step::Tile), 4);
    // In order: the bands, the per-frame passes, then slabs or tiles.
    const auto firstOther =
        std::find_if(steps.begin(), steps.end(), [](Step k) { return k != Step::ShadowBand; });
    ASSERT_NE(firstOther, steps.end());
    EXPECT_EQ(*firstOther, Step::PerFrame);
    EXPECT_EQ(std::count(firstOther, steps.end(), Step::ShadowBand), 0);
    EXPECT_EQ(tiled.shadowMapRenders(), renders0 + 1);
    EXPECT_EQ(differing(rgba8(tiled.ldrTexture()), expected), 0u) << "bytes of the refined frame";
    // With reuse on and the maps valid, the next refinement draws no band.
    tiled.setReuseShadowMaps(true);
    tiled.render(); // draws (reuse just switched on)
    tiled.beginRefinement(32);
    int bands = 0;
    for (done = false; !done;) {
        done = tiled.refineStep();
        bands += tiled.refinement().lastStep == Step::ShadowBand;
    }
    EXPECT_EQ(bands, 0);
}

namespace {

fs::path folder(const std::string& name) {
    const fs::path d = outputDir() / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

} // namespace

// The session's budget (view.refine_budget_ms) through `veil view --script` in a real window:
// fog.json at 96 x 64 in 48 px grid tiles (2 x 2: two 48 x 48 above, two 48 x 16 below),
// each refinement at the scene's camera
// (reset_camera renders it again).
// - 1e6 ms, which every step meets: the first refinement has no estimate, so its first step
//   takes the smallest tile (48 -> 24 -> 12 px: halved until at most kMinRefineTilePx = 16);
//   the rest of that grid tile goes as the split left it (three 12 px and three 24 px tiles),
//   then the other three grid tiles whole: 10 steps. The next refinement has the estimate and
//   takes the 4 grid tiles whole.
// - 0.001 ms, which no step meets: every tile is halved to at most 16 px a side: 16 tiles of
//   12 x 12 px per upper grid tile, 4 of 12 x 16 per lower one, 40 steps.
// - The screenshots of all three equal the refinement without a budget's bit for bit.
TEST(ViewRefineBudgetTest, TilesHalveUnderATightBudgetAndStayWholeUnderALooseOne) {
    const fs::path d = folder("view-refine-budget");
    auto at = [&](const std::string& n) { return (d / n).string(); };
    const nlohmann::json script = {
        {{"refine_budget_ms", 1000000}}, {{"refine_tile_px", 48}},
        {{"status", at("probe.json")}},  {{"screenshot", at("probe.png")}},
        {{"reset_camera", true}},        {{"status", at("loose.json")}},
        {{"refine_budget_ms", 0.001}},   {{"reset_camera", true}},
        {{"status", at("tight.json")}},  {{"screenshot", at("tight.png")}},
        {{"refine_budget_ms", 0}},       {{"reset_camera", true}},
        {{"status", at("none.json")}},   {{"screenshot", at("none.png")}}};
    std::ofstream(d / "script.json") << script.dump();
    const CommandResult r =
        runCommand("xvfb-run -a -s '-screen 0 640x480x24' " + veilExe() + " view " +
                   shellQuote(sourceDir() / "datasets/scenes/fog.json") +
                   " --width 96 --height 64 --set render.shadows.size=128 --set "
                   "render.fog_resolution=2 --script " +
                   shellQuote(d / "script.json"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    struct Want {
        const char* file;
        double budget;
        int steps, minTile;
    };
    for (const Want& w : {Want{"probe.json", 1e6, 10, 12}, Want{"loose.json", 1e6, 4, 48},
                          Want{"tight.json", 0.001, 40, 12}, Want{"none.json", 0.0, 4, 48}}) {
        const nlohmann::json st = readJson(d / w.file);
        const nlohmann::json& f = st["refinement"];
        SCOPED_TRACE(w.file);
        EXPECT_TRUE(st["errors"].empty()) << st;
        EXPECT_EQ(f["budget_ms"].get<double>(), w.budget) << f;
        EXPECT_EQ(f["tiles"], 4) << f;
        EXPECT_EQ(f["steps"], w.steps) << f;
        EXPECT_EQ(f["min_tile_px"], w.minTile) << f;
        EXPECT_EQ(f["max_tiles_per_ui_frame"], 1) << f;
        EXPECT_EQ(f["complete"], true) << f;
    }
    for (const char* n : {"probe.png", "tight.png"}) {
        const ImageDiff diff =
            compareImages(io::readImage(d / "none.png"), io::readImage(d / n), 3);
        EXPECT_EQ(diff.maxAbs, 0.0) << n;
    }
    const ImageF img = io::readImage(d / "none.png");
    const auto [lo, hi] = std::minmax_element(img.pixels.begin(), img.pixels.end());
    EXPECT_GT(*hi - *lo, 0.3f) << "a flat image";
}

} // namespace veil::test
