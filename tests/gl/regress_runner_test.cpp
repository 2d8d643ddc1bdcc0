// The regression runner and the frame capture called as libraries (src/regress, src/capture),
// in this process's GL context: what `veil regress` and `veil render --dump` do, without the
// binary. tests/gl/regress_cli_test.cpp and dump_test.cpp test the command line.
#include "capture/dump.h"
#include "capture/exr_output.h"
#include "frame/renderer.h"
#include "gl/gl_fixture.h"
#include "io/image_io.h"
#include "io/metrics.h"
#include "regress/runner.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() { return outputSubdir("regress-runner"); }

const char* kScene = R"({
  "render": {"width": 24, "height": 16, "oit": "blend"},
  "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0.5, 0]}],
  "lights": [{"type": "directional", "direction": [0.3, -1, -0.2], "intensity": 2}],
  "materials": {"m": {"base_color": 0.5}, "glass": {"base_color": 1, "alpha": 0.4}},
  "objects": [{"shape": {"type": "box", "size": [2, 1, 0.5]}, "material": "m"},
              {"shape": {"type": "sphere", "radius": 0.5, "segments": 16, "rings": 8},
               "material": "glass", "transform": {"translate": [0, 0.8, 1]}}]
})";

class RegressRunnerTest : public GlTest {};

} // namespace

TEST_F(RegressRunnerTest, RunsCasesAndWritesReferencesAndImages) {
    const fs::path d = dir() / "run";
    fs::remove_all(d);
    fs::create_directories(d);
    std::ofstream(d / "scene.json") << kScene;
    std::ofstream(d / "suite.json") << R"({"defaults": {"scene": "scene.json"}, "cases": [
        {"name": "same", "technique": "reference", "reference": "reference",
         "metrics": {"maxabs": 0}},
        {"name": "stored", "technique": "blend", "reference": "stored.exr",
         "metrics": {"maxabs": 0}},
        {"name": "far", "technique": "blend", "reference": "reference",
         "overrides": ["render.exposure=4"], "metrics": {"rmse": 0}}]})";
    const regress::Suite suite = regress::loadSuite(d / "suite.json", true);
    std::vector<std::string> seen;
    regress::RunOptions options;
    options.output = d / "report";
    options.update = true;
    options.onCase = [&](const regress::CaseResult& r) { seen.push_back(r.name); };

    const regress::CaseResult same = regress::runCase(suite.cases[0], info(), options);
    EXPECT_TRUE(same.passed) << same.error;
    EXPECT_EQ(same.technique, "reference");
    EXPECT_EQ(same.width, 24);
    ASSERT_EQ(same.metrics.size(), 1u);
    EXPECT_EQ(same.metrics[0].value, 0.0);
    for (const std::string* png : {&same.renderPng, &same.referencePng, &same.diffPng})
        EXPECT_TRUE(fs::exists(d / "report" / *png)) << *png;

    // With update, the stored reference is the render: it compares equal and says so.
    const regress::CaseResult stored = regress::runCase(suite.cases[1], info(), options);
    EXPECT_TRUE(stored.passed) << stored.error;
    EXPECT_NE(stored.updated.find("stored.exr (created)"), std::string::npos) << stored.updated;
    const ImageF written = io::readImage(d / "stored.exr");
    EXPECT_EQ(written.width, 24);

    // A whole shard in a context of its own: the callback sees every case in order.
    const regress::Report report = regress::runSuite(suite, options, {1, 2});
    context_->makeCurrent(); // runSuite's context was current until it ended
    ASSERT_EQ(report.cases.size(), 1u);
    EXPECT_EQ(report.cases[0].name, "stored");
    EXPECT_EQ(report.shard, "1/2");
    EXPECT_EQ(seen, std::vector<std::string>{"stored"});

    // blend differs from reference: a zero RMSE tolerance fails with the value recorded.
    const regress::CaseResult far = regress::runCase(suite.cases[2], info(), options);
    EXPECT_FALSE(far.passed);
    EXPECT_TRUE(far.error.empty()) << far.error;
    ASSERT_EQ(far.metrics.size(), 1u);
    EXPECT_GT(far.metrics[0].value, 0.0);
}

TEST_F(RegressRunnerTest, CaseThatCannotRenderIsAResultNotAnException) {
    const fs::path d = dir() / "broken";
    fs::remove_all(d);
    fs::create_directories(d);
    std::ofstream(d / "scene.json") << kScene;
    std::ofstream(d / "suite.json") << R"({"cases": [{"name": "a", "scene": "scene.json",
        "technique": "blend", "reference": "ref.exr", "metrics": {"rmse": 1}}]})";
    const regress::Suite suite = regress::loadSuite(d / "suite.json", true); // ref.exr missing
    regress::RunOptions options;
    options.output = d / "report";
    const regress::CaseResult r = regress::runCase(suite.cases[0], info(), options);
    EXPECT_FALSE(r.passed);
    EXPECT_NE(r.error.find("ref.exr"), std::string::npos) << r.error;
}

TEST_F(RegressRunnerTest, CaptureDumpsTheFrameAndItsDepth) {
    const fs::path d = dir() / "capture";
    fs::remove_all(d);
    fs::create_directories(d);
    std::ofstream(d / "scene.json") << kScene;
    const scene::Scene s = scene::loadScene(d / "scene.json");
    frame::Renderer renderer(s, info());
    renderer.render();
    const nlohmann::json manifest = capture::dumpFrame(renderer, d / "dump");
    EXPECT_EQ(manifest["frame_width"], 24);
    bool hdr = false;
    for (const auto& e : manifest["resources"])
        if (e["resource"] == "hdr") {
            hdr = true;
            EXPECT_TRUE(e["dumpable"].get<bool>());
            const ImageF dumped = io::readImage(d / "dump" / e["file"].get<std::string>());
            EXPECT_EQ(metrics::maxAbs(dumped, renderer.readHdr()), 0.0);
        }
    EXPECT_TRUE(hdr) << manifest.dump(2);

    const capture::FrameExtras extras = capture::captureExtras(renderer, false);
    ASSERT_EQ(extras.viewDepth.width, 24);
    // The box fills the image centre (finite depth), the corners see nothing (+inf).
    EXPECT_TRUE(std::isfinite(extras.viewDepth.at(12, 12, 0)));
    EXPECT_TRUE(std::isinf(extras.viewDepth.at(0, 0, 0)));
    EXPECT_THROW(capture::captureExtras(renderer, true), Error); // no fog for a fog AOV
}

} // namespace veil::test
