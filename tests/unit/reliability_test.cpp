// Hostile inputs to the readers and helpers below the command line, each of which once
// crashed or gave a wrong answer: suites and results.json nested 60,000 deep or with a key
// given twice, NaN pixels under every metric and in the heat map, glTF buffer URIs that
// leave the model's folder, node chains deeper than assimp's recursion survives, vertices
// near FLT_MAX, procedural volumes of size 1e30, the one option-number parser, orbit steps
// of 1e30 and view scripts that would overwrite themselves.
#include "app/cli_checks.h"
#include "base/error.h"
#include "io/metrics.h"
#include "regress/report.h"
#include "regress/suite.h"
#include "scene/mesh.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "viewer/session/view_session.h"
#include "viewer/view_script.h"
#include "voxelize/triangles.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir(const std::string& name) { return freshOutputDir("reliability", name); }

const char* kScene = R"({"cameras": [{"name": "c", "position": [0, 0, 4]}],
  "materials": {"m": {"alpha": 0.5}},
  "objects": [{"shape": {"type": "sphere", "radius": 0.5}, "material": "m"}]})";

std::string nested(std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();

ImageF flat(float v) {
    ImageF img(8, 6, 4);
    for (float& p : img.pixels)
        p = v;
    return img;
}

} // namespace

// Mutation: loadSuite back on nlohmann::json::parse -> SIGSEGV (depth) and the second case's
// "metrics" silently replaced (duplicate key).
TEST(ReliabilityTest, SuiteDepthAndDuplicateKeysAreRefusedNamingTheFile) {
    const fs::path d = dir("suite");
    writeTextFile(d / "scene.json", kScene);
    writeTextFile(d / "deep.json",
                  R"({"cases": [{"name": "a", "scene": "scene.json", "technique": )" +
                      nested(60000) + "}]}");
    const std::string deep = errorOf([&] { regress::loadSuite(d / "deep.json", false); });
    EXPECT_NE(deep.find("deep.json: invalid JSON: nested deeper than 256 levels"),
              std::string::npos)
        << deep;
    writeTextFile(d / "twice.json", R"({"cases": [{"name": "a", "scene": "scene.json",
        "technique": "blend", "reference": "reference", "metrics": {"rmse": 0.1},
        "metrics": {"rmse": 100}}]})");
    const std::string twice = errorOf([&] { regress::loadSuite(d / "twice.json", false); });
    EXPECT_NE(twice.find("twice.json: /cases/0/metrics: duplicate key 'metrics'"),
              std::string::npos)
        << twice;
}

// The results.json of a shard folder goes through the same parser (--merge reads it).
TEST(ReliabilityTest, ResultsFileDepthAndDuplicateKeysAreRefusedNamingTheFile) {
    const fs::path d = dir("results");
    writeTextFile(d / "results.json", R"({"suite": )" + nested(60000) + "}");
    const std::string deep = errorOf([&] { regress::readReport(d); });
    EXPECT_NE(deep.find("results.json"), std::string::npos) << deep;
    EXPECT_NE(deep.find("nested deeper than 256 levels"), std::string::npos) << deep;
    writeTextFile(d / "results.json",
                  R"({"suite": "a", "suite": "b", "suite_file": "s", "shard": "",
        "cases": [], "seconds": 0})");
    const std::string twice = errorOf([&] { regress::readReport(d); });
    EXPECT_NE(twice.find("duplicate key 'suite'"), std::string::npos) << twice;
}

// Mutation: maxAbs back on a plain std::max (0 for a NaN pixel) and compute() without the NaN
// scan (nrmse said inf, psnr/relmse/rmse NaN by luck).
TEST(ReliabilityTest, NanPixelsMakeEveryMetricNanAndFailEveryThreshold) {
    const ImageF ref = flat(0.5f);
    ImageF one = ref;
    one.at(3, 2, 1) = kNan;
    const ImageF all = flat(kNan);
    EXPECT_TRUE(std::isnan(metrics::maxAbs(one, ref)));
    EXPECT_TRUE(std::isnan(metrics::maxAbs(all, ref)));
    EXPECT_TRUE(std::isnan(metrics::percentileAbsError(one, ref)));
    EXPECT_TRUE(std::isnan(metrics::peak(one)));
    for (const std::string& name : metrics::metricNames())
        for (const auto& [image, reference] : std::vector<std::pair<const ImageF*, const ImageF*>>{
                 {&one, &ref}, {&all, &ref}, {&ref, &one}}) {
            const double v = metrics::compute(name, *image, *reference);
            EXPECT_TRUE(std::isnan(v)) << name << " = " << v;
            EXPECT_FALSE(
                metrics::withinThreshold(name, v, metrics::higherIsBetter(name) ? -1e300 : 1e300))
                << name;
        }
    // Without NaN the values are what they were: the scan changes nothing else.
    ImageF off = ref;
    off.at(1, 1, 0) = 0.75f;
    EXPECT_DOUBLE_EQ(metrics::compute("maxabs", off, ref), 0.25);
}

// Mutation: heatMap without the NaN/inf handling -> static_cast<int>(NaN) indexed the colour
// ramp out of bounds (SIGSEGV for --diff-scale nan and for NaN pixels).
TEST(ReliabilityTest, HeatMapOfNanPixelsAndNonFiniteScalesIsWhiteAndFinite) {
    const ImageF ref = flat(0.5f);
    ImageF img = ref;
    img.at(2, 2, 0) = kNan;
    img.at(4, 3, 2) = 0.75f;
    for (double scale : {0.0, double(kNan), std::numeric_limits<double>::infinity(), 0.1}) {
        const ImageF h = metrics::heatMap(img, ref, scale);
        for (float v : h.pixels)
            ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f) << scale;
        EXPECT_EQ(h.at(2, 2, 0), 1.0f) << scale; // NaN error: white
        EXPECT_EQ(h.at(2, 2, 2), 1.0f) << scale;
        EXPECT_EQ(h.at(0, 0, 0), 0.0f) << scale; // no error: black
    }
    // Automatic scale: the largest finite error (0.25) is white, not the NaN.
    EXPECT_EQ(metrics::heatMap(img, ref).at(4, 3, 1), 1.0f);
}

// Mutation: parseFiniteNumber accepting what strtod accepts (nan, inf, 1e400 = HUGE_VAL).
TEST(ReliabilityTest, OptionNumbersAreFiniteAndWhole) {
    for (const char* bad : {"", "nan", "NaN", "-nan", "inf", "-inf", "infinity", "1e400", " 1",
                            "1 ", "1x", "0x", "--1", "1,5"})
        EXPECT_FALSE(app::parseFiniteNumber(bad).has_value()) << "'" << bad << "'";
    EXPECT_EQ(app::parseFiniteNumber("1.5"), 1.5);
    EXPECT_EQ(app::parseFiniteNumber("-2"), -2.0);
    EXPECT_EQ(app::parseFiniteNumber("1e-3"), 1e-3);
    EXPECT_EQ(app::parseFiniteNumber("1.7976931348623157e308"), std::numeric_limits<double>::max());
    std::string text = "nan";
    EXPECT_FALSE(app::finiteRange(0.0, 1e6)(text).empty());
    text = "5";
    EXPECT_TRUE(app::finiteRange(0.0, 1e6)(text).empty());
}

// Mutation: bufferCapacity opening path.parent_path() / uri as before -> the files outside are
// read (their sizes accepted) and only the missing one is an error.
TEST(ReliabilityTest, GltfBufferUrisMustStayInsideTheModelsFolder) {
    const fs::path d = dir("gltf-uri");
    fs::create_directories(d / "model" / "sub");
    std::string bin(44, '\0');
    writeTextFile(d / "outside.bin", bin);
    writeTextFile(d / "model" / "sub" / "inside.bin", bin);
    fs::create_symlink(d / "outside.bin", d / "model" / "link.bin");
    const auto gltf = [&](const std::string& uri) {
        const fs::path p = d / "model" / "m.gltf";
        writeTextFile(p, R"({"asset":{"version":"2.0"},"buffers":[{"uri":")" + uri +
                             R"(","byteLength":44}]})");
        return p;
    };
    for (const std::string& uri : std::vector<std::string>{
             "../outside.bin", "sub/../../outside.bin", (d / "outside.bin").string(),
             "%2e%2e/outside.bin", "..%2Foutside.bin", "link.bin", "file:///etc/passwd",
             "/etc/passwd"}) {
        const std::string e = errorOf([&] { scene::loadMeshFile(gltf(uri)); });
        EXPECT_NE(e.find("m.gltf': glTF buffers[0].uri"), std::string::npos) << uri << ": " << e;
        EXPECT_NE(e.find("outside the model's folder"), std::string::npos) << uri << ": " << e;
    }
    // Inside the folder the check passes (assimp then finds no meshes in this file).
    const std::string inside = errorOf([&] { scene::loadMeshFile(gltf("sub/inside.bin")); });
    EXPECT_EQ(inside.find("outside the model's folder"), std::string::npos) << inside;
    EXPECT_EQ(inside.find("buffers[0]"), std::string::npos) << inside;
}

namespace {

// A glTF of one triangle whose mesh hangs at the end of a chain of `depth` nodes (or a cycle).
fs::path chainGltf(const fs::path& d, const std::string& name, int depth, bool cycle = false) {
    std::string bin;
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    bin.append(reinterpret_cast<const char*>(pos), sizeof(pos));
    writeTextFile(d / "tri.bin", bin);
    std::string nodes;
    for (int i = 0; i < depth; ++i) {
        nodes += i ? "," : "";
        if (i + 1 < depth)
            nodes += fmt::format(R"({{"children":[{}]}})", i + 1);
        else
            nodes += cycle ? R"({"children":[1],"mesh":0})" : R"({"mesh":0})";
    }
    const fs::path p = d / name;
    writeTextFile(
        p, R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[)" + nodes +
               R"(],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
               R"("buffers":[{"uri":"tri.bin","byteLength":36}],)"
               R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
               R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",)"
               R"("min":[0,0,0],"max":[1,1,0]}]})");
    return p;
}

} // namespace

// Mutation: no checkNodeHierarchy -> the 20,000-deep chain overflows the stack inside assimp
// (SIGSEGV); a cycle hangs or crashes it.
TEST(ReliabilityTest, DeepOrCyclicGltfNodeChainsAreRefusedBeforeAssimp) {
    const fs::path d = dir("gltf-chain");
    const auto t0 = std::chrono::steady_clock::now();
    const std::string deep =
        errorOf([&] { scene::loadMeshFile(chainGltf(d, "deep.gltf", 20000)); });
    EXPECT_NE(deep.find("deep.gltf': glTF node hierarchy is deeper than 256 levels"),
              std::string::npos)
        << deep;
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
              5.0 * kSlowBuildFactor);
    const std::string cyc =
        errorOf([&] { scene::loadMeshFile(chainGltf(d, "cycle.gltf", 5, true)); });
    EXPECT_NE(cyc.find("cycle.gltf': glTF nodes[1] is a child of two nodes"), std::string::npos)
        << cyc;
    // 256 levels load: the node transforms (identity) keep the triangle where it is.
    const auto meshes = scene::loadMeshFile(chainGltf(d, "ok.gltf", 256));
    ASSERT_EQ(meshes.size(), 1u);
    EXPECT_EQ(meshes[0].mesh.triangleCount(), 1u);
}

// Mutation: no kMaxMeshCoordinate check -> the mesh loads and voxelize's grid fitting
// overflows (hi - lo = inf).
TEST(ReliabilityTest, VerticesNearFltMaxAreRefusedNamingTheFile) {
    const fs::path d = dir("huge-mesh");
    writeTextFile(d / "huge.obj", "v -3e38 0 0\nv 3e38 0 0\nv 0 3e38 0\nf 1 2 3\n");
    const std::string e = errorOf([&] { scene::loadMeshFile(d / "huge.obj"); });
    EXPECT_NE(e.find("huge.obj': mesh"), std::string::npos) << e;
    EXPECT_NE(e.find("lies beyond 1e+18"), std::string::npos) << e;
    // A transform can carry a vertex that far too: the voxelizer's bounds refuse it.
    writeTextFile(d / "small.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const auto meshes = scene::loadMeshFile(d / "small.obj");
    voxelize::Triangles t = voxelize::fromMesh(
        meshes[0].mesh, glm::mat4(glm::vec4(3e38f, 0, 0, 0), glm::vec4(0, 1, 0, 0),
                                  glm::vec4(0, 0, 1, 0), glm::vec4(0, 0, 0, 1)));
    glm::vec3 lo, hi;
    const std::string v = errorOf([&] { t.bounds(lo, hi); });
    EXPECT_NE(v.find("too far out to voxelize"), std::string::npos) << v;
}

// Mutation: the size range back to kAny -> accepted; the render then coarsened to 1e23-unit
// voxels and ran for minutes.
TEST(ReliabilityTest, ProceduralVolumeSizeIsBoundedAtParse) {
    const fs::path d = dir("procedural");
    writeTextFile(d / "big.json", R"({"cameras": [{"name": "c", "position": [0, 0, 4]}],
        "volumes": [{"procedural": "smoke-ball", "size": [1e30, 1, 1]}]})");
    const std::string e = errorOf([&] { scene::loadScene(d / "big.json", {}); });
    EXPECT_NE(e.find("big.json"), std::string::npos) << e;
    EXPECT_NE(e.find("/volumes/0/size"), std::string::npos) << e;
}

// Mutation: Orbit::pan / orbitBy without the clamps -> target and distance inf (black frame).
TEST(ReliabilityTest, HugeOrbitPanStepsLeaveAFiniteCamera) {
    session::Orbit o;
    o.pan(1e30f, -1e30f);
    o.pan(1e30f, 1e30f);
    scene::Camera c;
    o.apply(c);
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(std::isfinite(c.position[i]) && std::abs(c.position[i]) <= 1e6f) << i;
        EXPECT_TRUE(std::isfinite(c.target[i]) && std::abs(c.target[i]) <= 1e6f) << i;
    }
}

// Mutation: no containment check in loadViewScript -> save_scene replaced the script it ran
// from; no magnitude check -> 1e300 became inf on the float conversion.
TEST(ReliabilityTest, ViewScriptsRefuseOverwritingThemselvesAndHugeSteps) {
    const fs::path d = dir("script");
    const fs::path script = d / "s.json";
    writeTextFile(script, R"([{"save_scene": ")" + script.string() + R"("}])");
    const std::string self = errorOf([&] { viewer::loadViewScript(script); });
    EXPECT_NE(self.find("would overwrite the script"), std::string::npos) << self;
    // A relative file is the script folder's: "s.json" is the script itself, another name not.
    writeTextFile(script, R"([{"screenshot": "s.json"}])");
    EXPECT_NE(errorOf([&] { viewer::loadViewScript(script); }).find("would overwrite the script"),
              std::string::npos);
    writeTextFile(script, R"([{"screenshot": "shot.json"}])");
    EXPECT_NO_THROW(viewer::loadViewScript(script));
    writeTextFile(script, R"([{"orbit": [1e300, 0]}])");
    const std::string huge = errorOf([&] { viewer::loadViewScript(script); });
    EXPECT_NE(huge.find("'orbit' expects two numbers in -1e6..1e6"), std::string::npos) << huge;
    writeTextFile(script, R"([{"orbit": [0, 0], "zoom": 1e300}])");
    EXPECT_NE(errorOf([&] { viewer::loadViewScript(script); }).find("'zoom' must be"),
              std::string::npos);
}

} // namespace veil::test
