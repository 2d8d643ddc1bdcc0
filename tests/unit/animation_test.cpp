// Time in scenes: sequence file patterns, frame resolution (range, step, offset, hold / loop /
// blank, missing files), keyframe interpolation against closed forms, the turntable, frame
// range syntax and the scene format's time keys.
#include "base/error.h"
#include "scene/animation.h"
#include "scene/scene.h"
#include "scene/timeline.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;
using scene::FileSequence;
using scene::Outside;

namespace {

// A folder with empty files (existence is what frame resolution looks at).
fs::path folderWith(const std::string& name, const std::vector<std::string>& files) {
    const fs::path dir = outputSubdir("animation") / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const std::string& f : files)
        std::ofstream(dir / f) << "x";
    return dir;
}

FileSequence sequenceIn(const fs::path& dir, const std::string& pattern, int first, int last,
                        int step = 1) {
    FileSequence s;
    s.pattern = *scene::parseFilePattern(dir / pattern);
    s.first = first;
    s.last = last;
    s.step = step;
    return s;
}

} // namespace

TEST(AnimationTest, PatternsPadAsWritten) {
    struct Case {
        const char* name;
        int frame;
        const char* file;
    } cases[] = {{"fire.####.vdb", 7, "fire.0007.vdb"},
                 {"fire.####.vdb", 12345, "fire.12345.vdb"},
                 {"fire.%04d.vdb", 7, "fire.0007.vdb"},
                 {"fire.%d.vdb", 7, "fire.7.vdb"},
                 {"fire.$F4.vdb", 42, "fire.0042.vdb"},
                 {"fire.$F.vdb", 42, "fire.42.vdb"},
                 {"embergen_fire_a_#.vdb", 10, "embergen_fire_a_10.vdb"}};
    for (const Case& c : cases) {
        const auto p = scene::parseFilePattern(fs::path("/d") / c.name);
        ASSERT_TRUE(p) << c.name;
        EXPECT_EQ(p->fileFor(c.frame).filename().string(), c.file) << c.name;
        EXPECT_EQ(p->frameOf(c.file), c.frame) << c.name;
    }
    const auto unpadded = scene::parseFilePattern("/d/a_#.vdb");
    EXPECT_FALSE(unpadded->frameOf("a_007.vdb")); // not how the pattern writes 7
    EXPECT_FALSE(unpadded->frameOf("a_.vdb"));
    EXPECT_FALSE(unpadded->frameOf("a_1x.vdb"));
    EXPECT_FALSE(scene::parseFilePattern("/d/plain.vdb"));
    // Padded wider than an int's 10 digits (found by the frames fuzz target: frameOf()
    // refused more than 9 digits, so such a sequence found none of its files).
    for (const char* wide : {"/d/w.%012d.vdb", "/d/w.$F12.vdb", "/d/w.############.vdb"}) {
        const auto p = scene::parseFilePattern(wide);
        ASSERT_TRUE(p) << wide;
        for (int f : {0, 12, 2147483647}) {
            EXPECT_EQ(p->frameOf(p->fileFor(f).filename().string()), f) << wide;
        }
        EXPECT_FALSE(p->frameOf("w.002147483648.vdb")) << wide; // past INT_MAX
    }
    EXPECT_FALSE(unpadded->frameOf("a_99999999999999999999.vdb"));
    EXPECT_NE(
        errorOf([] { scene::parseFilePattern("/d/a.##.%04d.vdb"); }).find("one frame pattern"),
        std::string::npos);
    EXPECT_NE(errorOf([] { scene::parseFilePattern("/d/a.%5d.vdb"); }).find("%0Nd"),
              std::string::npos);
}

TEST(AnimationTest, ExistingFramesFollowThePattern) {
    const fs::path dir = folderWith(
        "existing", {"s_1.vdb", "s_2.vdb", "s_10.vdb", "s_010.vdb", "s_0003.vdb", "other_4.vdb"});
    EXPECT_EQ(scene::existingFrames(*scene::parseFilePattern(dir / "s_#.vdb")),
              (std::vector<int>{1, 2, 10}));
    EXPECT_EQ(scene::existingFrames(*scene::parseFilePattern(dir / "s_####.vdb")),
              (std::vector<int>{3}));
}

TEST(AnimationTest, FramesResolveWithOffsetStepAndOutsideRules) {
    const fs::path dir = folderWith("resolve", {"f.1.vdb", "f.3.vdb", "f.5.vdb", "f.7.vdb"});
    FileSequence s = sequenceIn(dir, "f.#.vdb", 1, 7, 2); // 1, 3, 5, 7
    auto file = [&](int frame) {
        const scene::SequenceFrame r = scene::resolveSequenceFrame(s, frame, "v");
        return r.blank ? -1 : r.fileFrame;
    };
    EXPECT_EQ(file(1), 1);
    EXPECT_EQ(file(4), 3); // between steps: the earlier one
    EXPECT_EQ(file(7), 7);
    EXPECT_EQ(file(100), 7); // hold
    EXPECT_EQ(file(-100), 1);
    s.frameOffset = 2; // scene frame 3 shows file 5
    EXPECT_EQ(file(3), 5);
    s.frameOffset = 0;
    s.after = Outside::Loop;
    s.before = Outside::Loop;
    // Index (n - 1) / 2 taken modulo 4 frames: 9 -> index 4 -> 0 -> file 1; 0 -> index -1 -> 3.
    EXPECT_EQ(file(9), 1);
    EXPECT_EQ(file(11), 3);
    EXPECT_EQ(file(0), 7);
    EXPECT_EQ(file(-1), 7);
    EXPECT_EQ(file(-2), 5);
    s.after = Outside::Blank;
    s.before = Outside::Blank;
    EXPECT_EQ(file(8), 7); // still inside: 8 holds 7 (the range ends at 7 + step - 1)
    EXPECT_EQ(file(9), -1);
    EXPECT_EQ(file(0), -1);
    EXPECT_TRUE(scene::missingFrames(s).empty());
}

TEST(AnimationTest, MissingFrameIsAnErrorNamingTheFileOrHeld) {
    const fs::path dir = folderWith("missing", {"m.0001.vdb", "m.0002.vdb", "m.0004.vdb"});
    FileSequence s = sequenceIn(dir, "m.####.vdb", 1, 4);
    EXPECT_EQ(scene::missingFrames(s), std::vector<int>{3});
    const std::string e = errorOf([&] { scene::resolveSequenceFrame(s, 3, "volume 'smoke'"); });
    EXPECT_NE(e.find("volume 'smoke': frame 3"), std::string::npos) << e;
    EXPECT_NE(e.find((dir / "m.0003.vdb").string() + "' is missing"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos);
    s.holdMissing = true;
    const scene::SequenceFrame held = scene::resolveSequenceFrame(s, 3, "v");
    EXPECT_TRUE(held.held);
    EXPECT_EQ(held.fileFrame, 2); // the nearest earlier
}

TEST(AnimationTest, LinearAndCatmullRomMatchClosedForms) {
    scene::KeyChannel c;
    c.frames = {0, 10, 20, 30};
    c.values = {glm::vec3(0, 0, 0), glm::vec3(1, 2, 0), glm::vec3(3, 2, 1), glm::vec3(4, 0, 5)};
    using scene::Interpolation;
    for (std::size_t k = 0; k < 4; ++k) // the keys themselves, both ways
        for (auto i : {Interpolation::Linear, Interpolation::CatmullRom}) {
            const glm::vec3 v = scene::evaluate(c, i, c.frames[k]);
            for (int a = 0; a < 3; ++a)
                EXPECT_FLOAT_EQ(v[a], c.values[k][a]);
        }
    const glm::vec3 lin = scene::evaluate(c, Interpolation::Linear, 12.5); // t = 1/4
    EXPECT_FLOAT_EQ(lin.x, 1.5f);
    EXPECT_FLOAT_EQ(lin.z, 0.25f);
    // Uniform Catmull-Rom halfway between p1 and p2: (-p0 + 9 p1 + 9 p2 - p3) / 16.
    const glm::vec3 mid = scene::evaluate(c, Interpolation::CatmullRom, 15.0);
    const glm::vec3 expect =
        (-c.values[0] + 9.0f * c.values[1] + 9.0f * c.values[2] - c.values[3]) / 16.0f;
    for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(mid[a], expect[a], 1e-6);
    // End segment: p0 repeated: (-p0 + 9 p0 + 9 p1 - p2) / 16 at frame 5.
    const glm::vec3 first = scene::evaluate(c, Interpolation::CatmullRom, 5.0);
    const glm::vec3 expectFirst = (8.0f * c.values[0] + 9.0f * c.values[1] - c.values[2]) / 16.0f;
    for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(first[a], expectFirst[a], 1e-6);
    EXPECT_EQ(scene::evaluate(c, Interpolation::CatmullRom, -5.0), c.values[0]); // held
    EXPECT_EQ(scene::evaluate(c, Interpolation::Linear, 99.0), c.values[3]);
}

TEST(AnimationTest, TurntableOrbitsAboutUp) {
    scene::Camera c;
    c.position = {1.0f, 2.0f, 6.0f};
    c.target = {1.0f, 0.0f, 1.0f};
    c.up = {0.0f, 1.0f, 0.0f};
    scene::CameraAnimation a;
    a.turntable = {true, 1, 8, 360.0};
    // Frame 3 = 90 degrees: (0, 2, 5) from the target turns to (5, 2, 0) (R_y(90) z = x).
    const glm::vec3 p = scene::cameraAtFrame(c, a, 3).position;
    EXPECT_NEAR(p.x, 6.0f, 1e-5);
    EXPECT_NEAR(p.y, 2.0f, 1e-5);
    EXPECT_NEAR(p.z, 1.0f, 1e-5);
    const glm::vec3 back = scene::cameraAtFrame(c, a, 9).position; // a full turn
    EXPECT_NEAR(back.x, 1.0f, 1e-5);
    EXPECT_NEAR(back.z, 6.0f, 1e-5);
    EXPECT_EQ(scene::cameraAtFrame(c, a, 1).position, c.position);
}

TEST(AnimationTest, FrameRangeSyntax) {
    const scene::FrameRange r = scene::parseFrameRange("1-120:7");
    EXPECT_EQ(r.first, 1);
    EXPECT_EQ(r.last, 120);
    EXPECT_EQ(r.frames().size(), 18u); // 1, 8, ..., 120
    EXPECT_EQ(r.frames().back(), 120);
    EXPECT_EQ(scene::parseFrameRange("7").frames(), std::vector<int>{7});
    EXPECT_EQ(scene::parseFrameRange("-5--3").frames(), (std::vector<int>{-5, -4, -3}));
    for (const char* bad : {"", "a-b", "5-1", "1-5:0", "1-5:", "3:2", "1--"})
        EXPECT_NE(errorOf([&] { scene::parseFrameRange(bad); }).find("--frames"), std::string::npos)
            << bad;
}

TEST(AnimationTest, SceneFormatReadsTimeKeys) {
    const fs::path dir = folderWith("scene", {"smoke_2.vdb", "smoke_4.vdb", "smoke_8.vdb"});
    nlohmann::json doc = {
        {"time", {{"fps", 30}}},
        {"cameras",
         {{{"position", {0, 0, 5}},
           {"interpolation", "catmull-rom"},
           {"keys", {{{"frame", 2}, {"fov_y", 30}}, {{"frame", 8}, {"fov_y", 60}}}}}}},
        {"lights",
         {{{"direction", {0, -1, 0}}, {"keys", {{{"frame", 1}, {"direction", {1, 0, 0}}}}}}}},
        {"volumes",
         {{{"name", "smoke"}, {"path", "smoke_#.vdb"}, {"before", "blank"}, {"frame_offset", 1}}}}};
    const scene::AnimatedScene s = scene::parseAnimatedScene(doc, dir);
    ASSERT_TRUE(s.timeline.volumes[0]);
    const FileSequence& q = *s.timeline.volumes[0];
    EXPECT_EQ(q.first, 2); // the files found, their spacing's common divisor as the step
    EXPECT_EQ(q.last, 8);
    EXPECT_EQ(q.step, 2);
    EXPECT_EQ(q.before, Outside::Blank);
    EXPECT_EQ(s.timeline.time.fps, 30.0f);
    EXPECT_TRUE(s.timeline.animated());
    const scene::FrameRange r = scene::sceneFrameRange(s.timeline); // files 2-8 = 1-7, keys 1-8
    EXPECT_EQ(r.first, 1);
    EXPECT_EQ(r.last, 8);
    const scene::Scene at = scene::sceneAtFrame(s, 3); // file 4
    EXPECT_EQ(at.volumes[0].path, dir / "smoke_4.vdb");
    // Catmull-Rom through two keys (each end repeated): p1 + (p2 - p1) (t + 3t^2 - 2t^3) / 2.
    const double t = 1.0 / 6.0;
    EXPECT_NEAR(at.cameras[0].fovYDegrees, 30.0 + 15.0 * (t + 3 * t * t - 2 * t * t * t), 1e-4);
    EXPECT_EQ(at.lights[0].direction, glm::vec3(1, 0, 0));
    EXPECT_TRUE(scene::sceneAtFrame(s, 0).volumes.empty()); // file 1: before the first, blank

    // parseScene() / loadScene(): the scene at time.frame, else the first frame.
    EXPECT_EQ(scene::parseScene(doc, dir).volumes[0].path, dir / "smoke_2.vdb");
    nlohmann::json still = doc;
    still["time"]["frame"] = 3;
    EXPECT_EQ(scene::parseScene(still, dir).volumes[0].path, dir / "smoke_4.vdb");

    auto parseError = [&](nlohmann::json d) { return errorOf([&] { scene::parseScene(d, dir); }); };
    nlohmann::json bad = doc;
    bad["volumes"][0]["path"] = "smoke_2.vdb"; // a plain file takes no sequence keys
    EXPECT_NE(
        parseError(bad).find("/volumes/0/frame_offset: frame_offset needs a frame pattern in path"),
        std::string::npos)
        << parseError(bad);
    bad = doc;
    bad["volumes"][0]["path"] = "none_#.vdb";
    EXPECT_NE(parseError(bad).find("/volumes/0/path: no file matches the sequence 'none_#.vdb'"),
              std::string::npos)
        << parseError(bad);
    bad = doc;
    bad["volumes"][0]["before"] = "freeze";
    EXPECT_NE(parseError(bad).find("/volumes/0/before: unknown value 'freeze'"), std::string::npos);
    bad = doc;
    bad["cameras"][0]["keys"][1]["frame"] = 2;
    EXPECT_NE(parseError(bad).find("/cameras/0/keys/1/frame: key frames must increase"),
              std::string::npos)
        << parseError(bad);
    bad = doc;
    bad["volumes"][0]["frames"] = {1, 9, 2};
    const scene::AnimatedScene given = scene::parseAnimatedScene(bad, dir);
    EXPECT_EQ(given.timeline.volumes[0]->last, 9);
    EXPECT_EQ(scene::missingFrames(*given.timeline.volumes[0]), (std::vector<int>{1, 3, 5, 7, 9}));
    EXPECT_NE(errorOf([&] { scene::sceneAtFrame(given, 4); }).find("smoke_5.vdb' is missing"),
              std::string::npos);
}

} // namespace veil::test
