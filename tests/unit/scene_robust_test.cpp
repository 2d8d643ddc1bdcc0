// Hostile scene input: documents nested 500k deep, numbers that do not fit a double
// or a float, invalid UTF-8 in --set. Each ends in a veil::Error naming the file (or the
// override) and the JSON pointer; none crashes or lets an nlohmann exception escape.
#include "base/error.h"
#include "base/log.h"
#include "base/text.h"
#include "scene/json_text.h"
#include "scene/scene.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using nlohmann::json;
using namespace veil::scene;

namespace {

fs::path writeScene(const std::string& name, const std::string& text) {
    const fs::path dir = fs::path(VEIL_TEST_OUTPUT_DIR) / "scene_robust_test";
    fs::create_directories(dir);
    const fs::path path = dir / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

const std::string kScene = R"({
  "render": {"width": 64, "height": 48},
  "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0, 0]}],
  "lights": [{"type": "directional", "direction": [0, -1, 0]}]
})";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    text.replace(text.find(from), from.size(), to);
    return text;
}

std::string nested(std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

// The message of the veil::Error that loading throws; fails the test on anything else.
std::string loadError(const fs::path& path, const std::vector<std::string>& overrides = {}) {
    try {
        loadScene(path, overrides);
    } catch (const veil::Error& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not a veil::Error: " << e.what();
        return e.what();
    }
    ADD_FAILURE() << path << " loaded without error";
    return {};
}

} // namespace

// 500k levels overflowed the stack in nlohmann's recursive dump/destructor (SIGSEGV);
// 50k crashed under a 1 MiB stack. Both as the whole file and as a known key's value.
TEST(SceneRobustTest, DeepNestingIsRefusedNamingTheFile) {
    for (std::size_t depth : {std::size_t(257), std::size_t(50000), std::size_t(500000)}) {
        for (bool whole : {true, false}) {
            const std::string name = fmt::format("deep-{}-{}.json", depth, whole ? "file" : "key");
            const fs::path p =
                writeScene(name, whole ? nested(depth) : replaced(kScene, "64", nested(depth)));
            const std::string msg = loadError(p);
            EXPECT_NE(msg.find(name), std::string::npos) << msg;
            EXPECT_NE(msg.find("nested deeper than 256 levels"), std::string::npos) << msg;
            EXPECT_LT(msg.size(), 200u) << msg;
        }
    }
    // 256 levels are still a document (refused later for its shape, not its depth).
    const std::string msg = loadError(writeScene("deep-256.json", nested(256)));
    EXPECT_NE(msg.find("expected an object"), std::string::npos) << msg;
}

TEST(SceneRobustTest, DeepOverrideValueIsRefusedNamingTheOverride) {
    json doc = json::parse(kScene);
    try {
        applyOverrides(doc, {"render.camera=" + nested(50000)});
        ADD_FAILURE() << "a 50000-deep --set value was accepted";
    } catch (const veil::Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("override 'render.camera=[[["), std::string::npos) << msg;
        EXPECT_NE(msg.find("nested deeper than 256"), std::string::npos) << msg;
        EXPECT_LT(msg.size(), 400u) << msg;
    }
}

// log::debug("... {}", node->dump()) printed (and built) the whole value even when the
// debug level was off; at debug level the line is now bounded.
TEST(SceneRobustTest, OverrideDebugLogIsBounded) {
    const auto saved = veil::log::level();
    veil::log::setLevel(veil::log::Level::Debug);
    json doc = json::parse(kScene);
    testing::internal::CaptureStderr();
    applyOverrides(doc, {"render.camera=" + std::string(100000, 'x')});
    const std::string err = testing::internal::GetCapturedStderr();
    veil::log::setLevel(saved);
    EXPECT_NE(err.find("override render.camera"), std::string::npos) << err.substr(0, 200);
    EXPECT_LT(err.size(), 400u);
    EXPECT_EQ(doc["render"]["camera"].get<std::string>().size(), 100000u);
}

// nlohmann's out_of_range.406 escaped as a bare "[json.exception...]" line.
TEST(SceneRobustTest, DoubleOverflowNamesFileAndPointer) {
    const fs::path p = writeScene("width-1e400.json", replaced(kScene, "64", "1e400"));
    const std::string msg = loadError(p);
    EXPECT_NE(msg.find("width-1e400.json: /render/width: "), std::string::npos) << msg;
    EXPECT_NE(msg.find("1e400"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("[json.exception"), std::string::npos) << msg;
    // The pointer into an array element and past earlier elements.
    const std::string msg2 =
        loadError(writeScene("pos-1e999.json", replaced(kScene, "[0, 1, 4]", "[0, 1, -1e999]")));
    EXPECT_NE(msg2.find("/cameras/0/position/2: "), std::string::npos) << msg2;
    // An empty key is a pointer component too (RFC 6901).
    const std::string msg3 = loadError(writeScene(
        "empty-key.json",
        replaced(kScene, "\"render\"", "\"materials\": {\"\": {\"alpha\": 1e400}}, \"render\"")));
    EXPECT_NE(msg3.find("empty-key.json: /materials//alpha: "), std::string::npos) << msg3;
}

// Finite in double, infinite (or zero) in the floats the scene is stored in: was accepted
// and rendered with an infinite intensity or a NaN camera.
TEST(SceneRobustTest, NumbersThatDoNotFitAFloatAreRefused) {
    struct Case {
        std::string from, to, pointer;
    } cases[] = {
        {"[0, 1, 4]", "[0, 1, 1e39]", "/cameras/0/position/2"},
        {"\"direction\"", "\"intensity\": 1e39, \"direction\"", "/lights/0/intensity"},
        {"\"height\": 48}", "\"height\": 48, \"exposure\": 1e-50}", "/render/exposure"},
    };
    for (const Case& c : cases) {
        const std::string msg =
            loadError(writeScene("float-range.json", replaced(kScene, c.from, c.to)));
        EXPECT_NE(msg.find("float-range.json: " + c.pointer + ": "), std::string::npos) << msg;
        EXPECT_NE(msg.find("does not fit a 32-bit float"), std::string::npos) << msg;
    }
    // Each coordinate fits, their difference does not: the view matrix would be NaN.
    const std::string msg = loadError(
        writeScene("camera-overflow.json", replaced(replaced(kScene, "[0, 1, 4]", "[0, 0, 3e38]"),
                                                    "[0, 0, 0]", "[0, 0, -3e38]")));
    EXPECT_NE(msg.find("/cameras/0/target: "), std::string::npos) << msg;
}

// (1e30, 1e30, 0) is a direction: normalized in float its squared length overflowed and the
// light shone along (0, 0, 0). Normalized in double it is the diagonal.
TEST(SceneRobustTest, HugeLightDirectionIsNormalizedExactly) {
    const Scene s =
        loadScene(writeScene("dir-1e30.json", replaced(kScene, "[0, -1, 0]", "[1e30, 1e30, 0]")));
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_NEAR(s.lights[0].direction.x, std::sqrt(0.5), 1e-6);
    EXPECT_NEAR(s.lights[0].direction.y, std::sqrt(0.5), 1e-6);
    EXPECT_EQ(s.lights[0].direction.z, 0.0f);
    const Scene tiny =
        loadScene(writeScene("dir-1e-30.json", replaced(kScene, "[0, -1, 0]", "[0, -1e-30, 0]")));
    EXPECT_NEAR(tiny.lights[0].direction.y, -1.0, 1e-6);
}

// The string reached nlohmann's dump() in a message, which threw type_error.316 with no
// file or override named.
TEST(SceneRobustTest, InvalidUtf8InOverrideNamesTheOverride) {
    const fs::path p = writeScene("utf8.json", kScene);
    for (const std::string ov :
         {"render.camera=\xff", "render.width=\xc3(", "render.\xed\xa0\x80=1"}) {
        const std::string msg = loadError(p, {ov});
        EXPECT_NE(msg.find("utf8.json: override 'render."), std::string::npos) << msg;
        EXPECT_NE(msg.find("not valid UTF-8"), std::string::npos) << msg;
        EXPECT_EQ(veil::firstInvalidUtf8(msg), std::nullopt) << "the message itself is UTF-8";
    }
    // Valid multi-byte text still goes through.
    json doc = json::parse(kScene);
    applyOverrides(doc, {"render.camera=caméra"});
    EXPECT_EQ(doc["render"]["camera"], "caméra");
}

TEST(SceneRobustTest, Utf8CheckFollowsRfc3629) {
    EXPECT_EQ(veil::firstInvalidUtf8("plain"), std::nullopt);
    EXPECT_EQ(veil::firstInvalidUtf8("\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80"), std::nullopt);
    EXPECT_EQ(veil::firstInvalidUtf8("ab\xc0\xaf"), 2u);       // overlong '/'
    EXPECT_EQ(veil::firstInvalidUtf8("a\xed\xa0\x80"), 1u);    // surrogate U+D800
    EXPECT_EQ(veil::firstInvalidUtf8("\xf4\x90\x80\x80"), 0u); // above U+10FFFF
    EXPECT_EQ(veil::firstInvalidUtf8("\xe2\x82"), 0u);         // cut short
    EXPECT_EQ(veil::printable("a\xff\n"), "a\\xFF\\x0A");
    EXPECT_EQ(veil::printable(std::string(100, 'x'), 10), std::string(10, 'x') + "...");
}

TEST(SceneRobustTest, DescribeJsonIsBounded) {
    const json deep = json::parse(nested(200));
    EXPECT_LE(describeJson(deep, 60).size(), 60u);
    EXPECT_EQ(describeJson(json::parse(R"({"a":[1,2]})")), R"({"a":[1,2]})");
    EXPECT_EQ(describeJson(json(std::string("\xff"))), "\"\xef\xbf\xbd\""); // U+FFFD
    EXPECT_EQ(describeJson(json(std::string(100, 'y')), 10), "\"yyyyyy...");
}

// A FIFO (or /dev/zero) as the scene file blocked or read forever.
TEST(SceneRobustTest, NonRegularSceneFileIsRefused) {
    const fs::path fifo = fs::path(VEIL_TEST_OUTPUT_DIR) / "scene_robust_test" / "fifo.json";
    fs::create_directories(fifo.parent_path());
    fs::remove(fifo);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string msg = loadError(fifo);
    EXPECT_NE(msg.find("fifo.json': not a regular file"), std::string::npos) << msg;
    fs::remove(fifo);
    EXPECT_NE(loadError(fifo.parent_path()).find("not a regular file"), std::string::npos);
}

// nlohmann keeps the last of two equal keys, so the scene rendered 128 wide without a word.
TEST(SceneRobustTest, DuplicateKeyIsRefused) {
    const std::string msg = loadError(writeScene(
        "duplicate.json", replaced(kScene, "\"width\": 64", "\"width\": 64, \"width\": 128")));
    EXPECT_NE(msg.find("duplicate.json: /render/width: duplicate key 'width'"), std::string::npos)
        << msg;
    // The same key in different objects is fine.
    EXPECT_NO_THROW(loadScene(writeScene("same-key.json", kScene)));
}

// Seen while writing the scene fuzz target, confirmed as a timeout of veil_fuzz_scene
// (tests/fuzz/regressions/scene/generated-triangles-over-budget): 250 bytes asked for a 4096 x 4096
// plane and sphere, 67 M triangles, 13 s and 2 GB in the fuzz build; 2^26 particles would be 134 M.
// Generated shapes share one budget of 2^24 triangles, checked before a shape is made (the sum over
// shapes is not tested here: reaching it means generating 16 M triangles first).
TEST(SceneRobustTest, GeneratedTrianglesAreBoundedPerScene) {
    const std::string materials = R"("materials": {"m": {}}, "objects": [)";
    const std::string scene = replaced(kScene, R"("lights")", materials + "OBJECTS], \"lights\"");
    auto with = [&](const std::string& objects) { return replaced(scene, "OBJECTS", objects); };

    const std::string big = with(R"({"shape": {"type": "plane", "subdivisions": 4096},
         "material": "m"})");
    const std::string msg = loadError(writeScene("big_plane.json", big));
    EXPECT_NE(msg.find("/objects/0/shape"), std::string::npos) << msg;
    EXPECT_NE(msg.find("33554432 triangles"), std::string::npos) << msg;

    // 2^23 + 1 particles are 2^24 + 2 triangles: over the triangle budget, though their 1344
    // MiB of vertices fit render.geometry_budget_mib (2^26 particles hit that first).
    const std::string many = loadError(
        writeScene("many_particles.json",
                   with(R"({"shape": {"type": "particles", "count": 8388609}, "material": "m"})")));
    EXPECT_NE(many.find("16777218 triangles"), std::string::npos) << many;

    // The repository's largest generated scene stays far below it.
    EXPECT_NO_THROW(loadScene(fs::path(VEIL_SOURCE_DIR) / "datasets/scenes/oit-bench-1m.json"));
}
