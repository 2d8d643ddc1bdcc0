// The veil command against a third campaign's classes of bad input: usage errors exit 2
// everywhere, frame ranges past the limit are refused before anything is allocated, `veil
// info` counts without overflow and refuses an unknown grid, path-tracer work is estimated
// and refused past --time-limit, animated cameras are checked per frame, messages name what
// they should (the output, the pattern, the frame, the glTF node), a frame range into frames
// another run is writing is refused.
#include "base/output_lock.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path freshDir(const std::string& name) { return freshOutputDir("cli_classes", name); }
std::string q(const fs::path& p) { return shellQuote(p); }

const std::string kScene = R"({
  "render": {"width": 24, "height": 16},
  "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0, 0]}],
  "lights": [{"type": "directional", "direction": [0, -1, 0]}],
  "materials": {"m": {"base_color": 0.5}},
  "objects": [{"shape": {"type": "box", "size": [1, 1, 1]}, "material": "m"}]
})";

const std::string kBall = R"({
  "render": {"width": 64, "height": 36, "background": 1.0, "ambient": 0.0,
             "pathtraced": {"spp": 8, "seed": 3}},
  "cameras": [{"name": "c", "type": "orthographic", "position": [0, 0, 5],
               "target": [0, 0, 0], "ortho_height": 2, "near": 1, "far": 10}],
  "lights": [{"type": "directional", "direction": [0, -1, 0]}],
  "volumes": [{"procedural": "sphere", "size": 1.0, "voxel_size": 0.05,
               "density_scale": 2.0, "albedo": 0.9}]
})";

fs::path fireSequence() { return dataDir() / "vdb-embergen-fire-seq" / "embergen_fire_a_#.vdb"; }

// `veil <args>`: exit `status`, one "veil: error:" line holding every needle.
std::string expectError(const std::string& args, const std::vector<std::string>& needles,
                        int status) {
    const CommandResult r = runCommand(veilExe() + " " + args);
    EXPECT_EQ(r.exitCode, status) << args << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("veil: error: ", 0), 0u) << r.output;
    for (const std::string& n : needles)
        EXPECT_NE(r.output.find(n), std::string::npos) << "'" << n << "' not in: " << r.output;
    return r.output;
}

} // namespace

// Mutation: usageError() in renderFrames() back to VEIL_CHECK -> the --frames rows exit 1.
TEST(CliClassesTest, UsageErrorsExitTwoEverywhere) {
    const fs::path d = freshDir("usage");
    const std::string s = q(writeTextFile(d / "s.json", kScene));
    const std::string seq = q(fireSequence());
    const std::vector<std::pair<std::string, std::string>> rows = {
        {"render " + s + " --frames 1-2 --frame 1 -o " + q(d / "o.#.png"), "not both"},
        {"render " + s + " --resume -o " + q(d / "o.png"), "--resume goes with --frames"},
        {"render " + s + " --frames 1-2 -o " + q(d / "plain.png"), "has no frame pattern"},
        {"render " + s + " --frames 1-2 --half -o " + q(d / "o.#.png"), "--half needs an .exr"},
        {"render " + s + " --frames 1-2 --dump " + q(d / "dump") + " -o " + q(d / "o.#.png"),
         "--dump is for one still frame"},
        {"render " + s + " --frames 1-2 --compare-to reference -o " + q(d / "o.#.png"),
         "--compare-to is for one still frame"},
        {"render " + s + " --frames 1-2 --aov fog -o " + q(d / "o.#.exr"), "--aov"},
        {"render " + s + " --frames 1-2 --oit all -o " + q(d / "o.#.png"), "--oit all"},
        {"render " + s + " --frames 1-2 --integrator pathtraced -o " + q(d / "o.#.exr"),
         "--integrator pathtraced is for one still frame"},
        {"render " + s + " --frames 1-2 -o " + q(d / "o.#.jpg"), "must end in .png, .exr"},
        {"render " + s + " --frames 1-2 --report " + q(d / "r.txt") + " -o " + q(d / "o.#.png"),
         "must end in .json"},
        {"render " + s + " --integrator pathtraced --half -o " + q(d / "o.exr"), "--half"},
        {"render " + s + " --integrator pathtraced --shadows all -o " + q(d / "o.exr"),
         "--shadows all"},
        {"render " + s + " --oit all --shadows all -o " + q(d / "o.png"), "one sheet at a time"},
        {"render " + s + " --frames 1-1000000000 -o " + q(d / "o.#.png"), "1000000000 frames"},
        {"export " + seq + " --frames 1-3 -o " + q(d / "f.vti"), "has no frame pattern"},
        {"voxelize " + q(d / "m.#.obj") + " -o " + q(d / "v.vdb"), "is a file sequence"},
    };
    for (const auto& [args, needle] : rows)
        expectError(args, {needle}, 2);
    EXPECT_TRUE(!fs::exists(d / "dump") || fs::is_empty(d / "dump"));
    EXPECT_FALSE(fs::exists(d / "plain.png"));
}

// Mutation: kMaxRangeFrames check removed from parseFrameRange -> the run allocates 2^32
// frames and ends in "out of memory" after seconds (or hangs); here it ends at once.
TEST(CliClassesTest, HugeFrameRangesAreRefusedAtOnceWithASplit) {
    const fs::path d = freshDir("huge");
    const std::string s = q(writeTextFile(d / "s.json", kScene));
    const auto start = std::chrono::steady_clock::now();
    const std::string out = expectError(
        "render " + s + " --frames -2147483648-2147483647 -o " + q(d / "o.#.png"),
        {"4294967296 frames, over the 100000", "--frames -2147483648--2147383649 first"}, 2);
    EXPECT_EQ(out.find("is not an option"), std::string::npos) << out;
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              10.0);
    expectError("export " + q(fireSequence()) + " --frames 1-200000 -o " + q(d / "f.#.vti"),
                {"200000 frames"}, 2);
}

// Mutation: printSequence() without `required` -> --grid nosuch exits 0.
TEST(CliClassesTest, InfoOfASequenceRefusesAnUnknownGridAndCountsMissingFrames) {
    expectError("info " + q(fireSequence()) + " --grid nosuch",
                {"--grid 'nosuch'", "no file of the sequence", "grids: flames, temperature"}, 1);
    const fs::path d = freshDir("info");
    fs::copy_file(dataDir() / "vdb-embergen-fire-seq" / "embergen_fire_a_1.vdb", d / "f_1.vdb");
    nlohmann::json doc = nlohmann::json::parse(kScene);
    doc["volumes"] = {{{"path", (d / "f_#.vdb").string()},
                       {"grid", "flames"},
                       {"frames", {1, 1000000000}},
                       {"missing", "hold"}}};
    const fs::path scene = writeTextFile(d / "seq.json", doc.dump());
    CommandResult r = runCommand(veilExe() + " info " + q(scene));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("(999999999 in all)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("time       frames 1-1000000000"), std::string::npos) << r.output;
    // A frame_offset that takes scene frames out of the int range is refused.
    doc["volumes"][0]["frames"] = {-1073741824, 1073741824};
    doc["volumes"][0]["frame_offset"] = -1073741824;
    r = runCommand(veilExe() + " info " + q(writeTextFile(d / "over.json", doc.dump())));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("/volumes/0/frame_offset"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("scene frames 0-2147483648, outside the -1073741824..1073741824"),
              std::string::npos)
        << r.output;
}

// Mutation: the pilot's refusal removed from pathTrace() -> the 16777216 spp render runs for
// hours; spp 1 back to a minimum of 1 -> an all-zero standard error image is written.
TEST(CliClassesTest, PathTracerWorkIsEstimatedAndRefusedPastTheLimit) {
    const fs::path d = freshDir("pathtraced");
    const std::string s = q(writeTextFile(d / "ball.json", kBall));
    const auto start = std::chrono::steady_clock::now();
    expectError("render " + s +
                    " --integrator pathtraced --set render.pathtraced.spp=16777216 -o " +
                    q(d / "b.exr"),
                {"would take about", "over --time-limit 3600 s", "raise --time-limit"}, 1);
    // A path that alone runs for a long time: refused from the lower bound while it runs.
    expectError("render " + s +
                    " --integrator pathtraced --set render.pathtraced.max_bounces=1048576 --set "
                    "render.pathtraced.spp=4096 --set volumes.0.albedo=1 --set "
                    "volumes.0.density_scale=2000 --time-limit 60 -o " +
                    q(d / "b.exr"),
                {"would take", "over --time-limit 60 s"}, 1);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              30.0 * kSlowBuildFactor);
    EXPECT_FALSE(fs::exists(d / "b.exr"));
    EXPECT_FALSE(fs::exists(d / "b-stderr.exr"));
    expectError("render " + s + " --integrator pathtraced --set render.pathtraced.spp=1 -o " +
                    q(d / "b.exr"),
                {"/render/pathtraced/spp", "[2, 16777216]"}, 1);
    // Within the limit it renders, as before.
    const CommandResult r =
        runCommand(veilExe() + " render " + s + " --integrator pathtraced -o " + q(d / "ok.exr"));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("8 spp"), std::string::npos) << r.output;
}

// Mutation: checkCamerasAtFrame() not called -> frames 2-3 render black and exit 0.
TEST(CliClassesTest, AnimatedCamerasAreCheckedAtEveryFrame) {
    const fs::path d = freshDir("camera");
    nlohmann::json doc = nlohmann::json::parse(kScene);
    // The position passes through the target at frame 2.
    doc["cameras"][0]["keys"] = {{{"frame", 1}, {"position", {0, 0, -4}}},
                                 {{"frame", 3}, {"position", {0, 0, 4}}}};
    std::string s = q(writeTextFile(d / "through.json", doc.dump()));
    expectError("render " + s + " --frames 1-3 -o " + q(d / "t.#.png"),
                {"camera 'c'", "at frame 2", "equals its target"}, 1);
    EXPECT_FALSE(fs::exists(d / "t.1.png"));
    // Catmull-Rom fov keys overshooting past 180 degrees.
    doc = nlohmann::json::parse(kScene);
    doc["cameras"][0]["interpolation"] = "catmull-rom";
    doc["cameras"][0]["keys"] = {{{"frame", 1}, {"fov_y", 10}},
                                 {{"frame", 3}, {"fov_y", 179}},
                                 {{"frame", 5}, {"fov_y", 179}}};
    s = q(writeTextFile(d / "fov.json", doc.dump()));
    expectError("render " + s + " --frames 1-5 -o " + q(d / "f.#.png"),
                {"at frame 4", "fov_y 189.6 degrees, outside (0, 180)"}, 1);
    EXPECT_FALSE(fs::exists(d / "f.1.png"));
    // A static scene's range warns that its frames are identical; one frame is "frame".
    s = q(writeTextFile(d / "static.json", kScene));
    const CommandResult w =
        runCommand(veilExe() + " render " + s + " --frames 1-2 -o " + q(d / "s.#.png"));
    EXPECT_EQ(w.exitCode, 0) << w.output;
    EXPECT_NE(w.output.find("its 2 frames are identical"), std::string::npos) << w.output;
    const CommandResult one =
        runCommand(veilExe() + " render " + s + " --frame 1 -o " + q(d / "one.#.png"));
    EXPECT_NE(one.output.find("wrote 1 frame ("), std::string::npos) << one.output;
}

// Mutation: the collapsed-mesh check removed from sceneForMesh() -> OpenVDB's
// "ArithmeticError: Non-zero scale values required".
TEST(CliClassesTest, VoxelizeNamesTheCollapsingGltfNodeAndTheFrame) {
    const fs::path d = freshDir("voxelize");
    // One triangle under a node scaled by 0 (data URI buffer: 3 float positions, 3 indices).
    const std::string gltf = R"({"asset": {"version": "2.0"}, "scene": 0,
      "scenes": [{"nodes": [0]}], "nodes": [{"name": "Flat", "mesh": 0, "scale": [0, 0, 0]}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
      "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                      {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, 0], "max": [1, 1, 0]},
                    {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
    writeTextFile(d / "z.1.gltf", gltf);
    expectError("voxelize " + q(d / "z.1.gltf") + " --res 16 -o " + q(d / "z.vdb"),
                {"z.1.gltf", "no extent to voxelize", "nodes[0] 'Flat' (scale [0,0,0])"}, 1);
    expectError("voxelize " + q(d / "z.#.gltf") + " --frames 1-1 --res 16 -o " + q(d / "z.#.vdb"),
                {"frame 1 (", "nodes[0] 'Flat'"}, 1);
    EXPECT_FALSE(fs::exists(d / "z.vdb"));
}

// Mutation: the OutputLock in runRenderFrames() removed -> the run writes frames 1-3 beside
// the other run holding frame 2 (before: two runs into one pattern both exited 0 and left
// frames of two sizes).
TEST(CliClassesTest, FramesAnotherRunIsWritingAreRefused) {
    const fs::path d = freshDir("lock");
    const std::string s = q(writeTextFile(d / "s.json", kScene));
    const fs::path pattern = d / "o.#.png";
    {
        // This process stands for a veil render writing frame 2 of the pattern.
        const OutputLock other(pattern, {2}, "veil render");
        expectError("render " + s + " --frames 1-3 -o " + q(pattern),
                    {"frame 2 of output '" + pattern.string() + "'", "another veil render",
                     "pid " + std::to_string(::getpid()), other.file().string()},
                    1);
        EXPECT_FALSE(fs::exists(d / "o.1.png"));
        // Other frames of the pattern (a slice of a Slurm array) render beside it.
        const CommandResult r =
            runCommand(veilExe() + " render " + s + " --frames 3-4 -o " + q(pattern));
        EXPECT_EQ(r.exitCode, 0) << r.output;
        EXPECT_TRUE(fs::exists(d / "o.4.png"));
    }
    const CommandResult r =
        runCommand(veilExe() + " render " + s + " --frames 1-3 -o " + q(pattern));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(d / "o.2.png"));
    EXPECT_FALSE(fs::exists(OutputLock::fileFor(pattern))) << "the lock file is left behind";
}

// Mutation: the empty-name check removed -> temperature_grid "" renders without emission.
TEST(CliClassesTest, EmptyTemperatureGridAndOutOfRangePropertiesAreRefused) {
    const fs::path d = freshDir("properties");
    nlohmann::json doc = nlohmann::json::parse(kScene);
    doc["volumes"] = {
        {{"path", (dataDir() / "vdb-embergen-fire-seq" / "embergen_fire_a_1.vdb").string()},
         {"grid", "flames"},
         {"temperature_grid", ""}}};
    const std::string s = q(writeTextFile(d / "t.json", doc.dump()));
    expectError("info " + s, {"/volumes/0/temperature_grid", "must name a grid"}, 1);
    doc["volumes"][0].erase("temperature_grid");
    const std::string ok = q(writeTextFile(d / "ok.json", doc.dump()));
    expectError("render " + ok + " --set volumes.0.temperature_intensity=1e30 -o " + q(d / "o.png"),
                {"temperature_intensity"}, 1);
    for (const char* cell : {"0", "1e6"})
        expectError("render " + ok + " --set render.fog_scattered_light_cell=" + cell + " -o " +
                        q(d / "o.png"),
                    {"fog_scattered_light_cell"}, 1);
    EXPECT_FALSE(fs::exists(d / "o.png"));
}

// Mutation: the integrators left out of `veil techniques` -> "unknown technique 'pathtraced'";
// didYouMean() left out of Obj -> no suggestion for a misspelt --set key.
TEST(CliClassesTest, TechniquesListThePathTracerAndSetKeysGetASuggestion) {
    const CommandResult r = runCommand(veilExe() + " techniques pathtraced");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("integrator pathtraced"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("max_bounces"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("range [2, 16777216]"), std::string::npos) << r.output;
    expectError("techniques pathtrace", {"did you mean 'pathtraced'?"}, 2);
    const fs::path d = freshDir("suggest");
    const std::string s = q(writeTextFile(d / "s.json", kScene));
    expectError("render " + s + " --set render.exposur=2 -o " + q(d / "o.png"),
                {"/render/exposur: unknown key (did you mean 'exposure'?)"}, 1);
}

// Mutation: the timeline check removed from ScriptRunner::beforeFrame() -> the script exits 0
// with the one frame the scene has.
TEST(CliClassesTest, ViewerTimeActionsOnAStaticSceneAreRefused) {
    if (runCommand("command -v xvfb-run").exitCode != 0) GTEST_SKIP() << "no xvfb-run";
    const fs::path d = freshDir("view");
    const std::string s = q(writeTextFile(d / "s.json", kScene));
    const fs::path script =
        writeTextFile(d / "script.json", R"([{"frame": 3}, {"screenshot": "shot.png"}])");
    const CommandResult r = runCommand("xvfb-run -a -s '-screen 0 640x480x24' " + veilExe() +
                                       " view " + s + " --script " + q(script));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("action 0 (frame): the scene has no timeline"), std::string::npos)
        << r.output;
}

} // namespace veil::test
