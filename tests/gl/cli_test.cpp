// The veil command end to end: success writes image + report; bad input ends in one clear
// line on stderr, a non-zero exit and no output file.
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() {
    const fs::path d = outputDir() / "cli";
    fs::create_directories(d);
    return d;
}

fs::path writeFile(const std::string& name, const std::string& text) {
    const fs::path p = dir() / name;
    std::ofstream(p) << text;
    return p;
}

const char* kValidScene = R"({
  "render": {"width": 64, "height": 48},
  "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0, 0]}],
  "lights": [{"type": "directional", "direction": [0, -1, 0]}],
  "materials": {"m": {"base_color": 0.5}},
  "objects": [{"shape": {"type": "box", "size": [1, 1, 1]}, "material": "m"}]
})";

// Runs `veil render <scene> -o <out>` expecting failure; returns the output.
std::string expectRenderFails(const fs::path& scene, const fs::path& out) {
    fs::remove(out);
    const CommandResult r =
        runCommand(veilExe() + " render '" + scene.string() + "' -o '" + out.string() + "'");
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_FALSE(fs::exists(out)) << "a failed render must leave no output file";
    // No temporary left behind either.
    for (const auto& e : fs::directory_iterator(out.parent_path()))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
    // One clear line.
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find("veil: error:"), std::string::npos) << r.output;
    return r.output;
}

} // namespace

TEST(CliTest, RenderWritesImageAndReport) {
    const fs::path scene = writeFile("valid.json", kValidScene);
    const fs::path out = dir() / "valid.png", report = dir() / "valid-report.json";
    fs::remove(out);
    fs::remove(report);
    const CommandResult r = runCommand(veilExe() + " render '" + scene.string() + "' -o '" +
                                       out.string() + "' --report '" + report.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(out));
    std::ifstream in(report);
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["width"], 64);
    EXPECT_EQ(j["height"], 48);
    EXPECT_FALSE(j["renderer"].get<std::string>().empty());
    std::vector<std::string> names;
    for (const auto& p : j["passes"]) {
        names.push_back(p["name"]);
        EXPECT_GE(p["ms"].get<double>(), 0.0);
    }
    EXPECT_EQ(names,
              (std::vector<std::string>{"shadow", "opaque", "transparent", "resolve", "tonemap"}));
}

TEST(CliTest, MalformedSceneIsOneClearError) {
    const fs::path scene = writeFile("malformed.json", std::string(kValidScene).substr(0, 90));
    const std::string msg = expectRenderFails(scene, dir() / "malformed.png");
    EXPECT_NE(msg.find("malformed.json"), std::string::npos) << msg;
}

TEST(CliTest, UnknownKeyNamesItsPath) {
    std::string text = kValidScene;
    text.replace(text.find("\"size\""), 6, "\"sise\"");
    const fs::path scene = writeFile("unknown-key.json", text);
    const std::string msg = expectRenderFails(scene, dir() / "unknown-key.png");
    EXPECT_NE(msg.find("/objects/0/shape/sise"), std::string::npos) << msg;
}

TEST(CliTest, MissingMeshFileIsNamed) {
    std::string text = kValidScene;
    text.replace(text.find("\"shape\": {\"type\": \"box\", \"size\": [1, 1, 1]}"),
                 std::string("\"shape\": {\"type\": \"box\", \"size\": [1, 1, 1]}").size(),
                 "\"mesh\": \"no-such-mesh.glb\"");
    const fs::path scene = writeFile("missing-mesh.json", text);
    const std::string msg = expectRenderFails(scene, dir() / "missing-mesh.png");
    EXPECT_NE(msg.find("no-such-mesh.glb"), std::string::npos) << msg;
}

TEST(CliTest, MissingSceneAndBadOutputAndUnknownTechnique) {
    expectRenderFails(dir() / "does-not-exist.json", dir() / "nothing.png");
    const fs::path scene = writeFile("valid2.json", kValidScene);
    expectRenderFails(scene, dir() / "image.bmp");
    const fs::path out = dir() / "unknown-oit.png";
    fs::remove(out);
    const CommandResult r = runCommand(veilExe() + " render '" + scene.string() + "' -o '" +
                                       out.string() + "' --oit no-such-technique");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("blend"), std::string::npos) << "should list known techniques";
    EXPECT_FALSE(fs::exists(out));
}

TEST(CliTest, NoGlDeviceIsOneClearError) {
    const fs::path scene = writeFile("valid3.json", kValidScene);
    const fs::path out = dir() / "nodevice.png";
    fs::remove(out);
    const CommandResult r = runCommand("VEIL_EGL_DEVICE=97 " + veilExe() + " render '" +
                                       scene.string() + "' -o '" + out.string() + "'");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("EGL device 97"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST(CliTest, InfoListsVdbGridsAndRefusesCorruptFiles) {
    const fs::path vdb = dataDir() / "vdb-smoke/smoke.vdb";
    ASSERT_TRUE(fs::exists(vdb)) << vdb;
    CommandResult r = runCommand(veilExe() + " info '" + vdb.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("'density' float"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("1049275 active voxels"), std::string::npos) << r.output;
    // A truncated copy must be refused with a message, not a crash.
    std::ifstream in(vdb, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const fs::path cut = writeFile("truncated.vdb", bytes.substr(0, bytes.size() / 3));
    r = runCommand(veilExe() + " info '" + cut.string() + "'");
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("veil: error:"), std::string::npos) << r.output;
    r = runCommand(veilExe() + " info '" + (dir() / "none.vdb").string() + "'");
    EXPECT_NE(r.exitCode, 0);
}

TEST(CliTest, InfoSummarisesScene) {
    const CommandResult r = runCommand(veilExe() + " info '" +
                                       (sourceDir() / "datasets/scenes/room.json").string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("11 ("), std::string::npos) << r.output; // 11 objects
    EXPECT_NE(r.output.find("spot"), std::string::npos);
}

} // namespace veil::test
