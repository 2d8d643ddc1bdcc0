// A stage added to the frame from the stage template (src/frame/stages/_template), through
// Renderer::insertStage alone: nothing of the renderer names it. Checked against the frame
// without it, which the stage did not produce: its pass scales the HDR image by `gain`, so
// every pixel is gain x the pixel of the plain frame. Both images are RGBA16F; a half times
// 0.5 is exactly a half (above the subnormals), so the tolerance is one half-float rounding
// step (2^-10 relative: llvmpipe rounds toward zero) and 2^-24 absolute. The stage runs per
// refinement tile (scope Pixels, the context's region): the tiled frame equals render() bit for
// bit. An unknown insertion point or a pass list that does not validate leaves the stages.
#include "base/error.h"
#include "frame/renderer.h"
#include "frame/stages/_template/template_stage.h"
#include "gl_fixture.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace veil::test {

namespace {

scene::Scene glassFogScene() {
    return scene::parseScene(nlohmann::json::parse(R"({
      "render": {"width": 48, "height": 32, "oit": "wboit", "fog_steps": 8},
      "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0.5, 0]}],
      "lights": [{"type": "directional", "direction": [0, -1, -0.3], "intensity": 2,
                  "shadows": true}],
      "materials": {"glass": {"base_color": 1, "alpha": 0.5}, "floor": {"base_color": 0.6}},
      "objects": [{"shape": {"type": "box", "size": [1, 1, 0.1]}, "material": "glass"},
                  {"shape": {"type": "plane", "size": [6, 6]}, "material": "floor"}],
      "volumes": [{"procedural": "sphere", "size": 1, "voxel_size": 0.1, "density_scale": 2}]
    })"),
                             ".");
}

frame::Renderer::StageFactory templateStage(double gain) {
    return [gain](gpu::ProgramManager& programs) {
        return std::make_unique<frame::TemplateStage>(
            programs, frame::TemplateStage::schema().resolve({{"gain", gain}}, "test"));
    };
}

std::vector<std::string> passNames(const frame::Renderer& r) {
    std::vector<std::string> names;
    for (const frame::Pass& p : r.passes().passes())
        names.push_back(p.name);
    return names;
}

} // namespace

class StageTemplateGLTest : public GlTest {};

TEST_F(StageTemplateGLTest, InsertedStageScalesTheFrameItRuns) {
    const scene::Scene sc = glassFogScene();
    frame::Renderer r(sc, info());
    r.render();
    const gpu::ImageF plain = r.readHdr();
    const std::vector<std::string> plainPasses = passNames(r);

    constexpr double kGain = 0.5;
    r.insertStage(templateStage(kGain), "tonemap");
    const std::vector<std::string> stages = r.stageNames();
    const auto at = std::find(stages.begin(), stages.end(), "template");
    ASSERT_NE(at, stages.end());
    EXPECT_EQ(*(at + 1), "tonemap");
    // One pass more, right before tonemap; the others as they were.
    std::vector<std::string> expected = plainPasses;
    expected.insert(std::find(expected.begin(), expected.end(), "tonemap"), "template");
    EXPECT_EQ(passNames(r), expected);

    r.render();
    const gpu::ImageF scaled = r.readHdr();
    ASSERT_EQ(scaled.pixels.size(), plain.pixels.size());
    int lit = 0;
    for (std::size_t i = 0; i < plain.pixels.size(); ++i) {
        if (i % 4 == 3) continue; // alpha stays
        const double want = kGain * plain.pixels[i];
        EXPECT_NEAR(scaled.pixels[i], want, std::ldexp(std::abs(want), -10) + std::ldexp(1.0, -24))
            << "component " << i;
        lit += plain.pixels[i] > 0.01f;
    }
    EXPECT_GT(lit, 100); // the frame is not black: the comparison means something

    // Per tile (the viewer's refinement): the same image bit for bit.
    r.beginRefinement(16);
    while (!r.refineStep()) {
    }
    const gpu::ImageF tiled = r.readHdr();
    EXPECT_EQ(tiled.pixels, scaled.pixels);
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(StageTemplateGLTest, BadInsertionLeavesTheStages) {
    const scene::Scene sc = glassFogScene();
    frame::Renderer r(sc, info());
    const std::vector<std::string> stages = r.stageNames();
    const std::vector<std::string> passes = passNames(r);
    try {
        r.insertStage(templateStage(2.0), "no-such-stage");
        FAIL() << "inserted before a stage that does not exist";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no-such-stage"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("transparency"), std::string::npos) << e.what();
    }
    // Before the shadows: its pass reads hdr, which no earlier pass writes.
    EXPECT_THROW(r.insertStage(templateStage(2.0), "shadows"), Error);
    EXPECT_EQ(r.stageNames(), stages);
    EXPECT_EQ(passNames(r), passes);
    r.render();
    VEIL_EXPECT_NO_GL_ERROR();
}

} // namespace veil::test
