// `veil render -o out.exr` end to end: float32 R, G, B, A, Z (+ fog AOVs),
// read back through OpenImageIO; Z against the analytic view depth of a ground plane;
// header metadata against independently computed values (sha256sum, glm::lookAt).
#include "support/test_support.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() {
    const fs::path d = outputDir() / "render_exr";
    fs::create_directories(d);
    return d;
}

// A 40 x 40 ground plane at y = 0 seen from (0, 2, 4) looking at (0, 1, 0): the sky above
// the horizon has no opaque surface. A homogeneous fog for the AOV case.
const char* kScene = R"({
  "render": {"width": 80, "height": 60, "background": 0.7},
  "cameras": [{"name": "low", "position": [0, 2, 4], "target": [0, 1, 0], "fov_y": 50,
               "near": 0.1, "far": 200}],
  "lights": [{"type": "directional", "direction": [0, -1, 0]}],
  "materials": {"m": {"base_color": 0.5}},
  "objects": [{"shape": {"type": "plane", "size": [40, 40]}, "material": "m"}]
})";

struct Exr {
    OIIO::ImageSpec spec;
    std::vector<float> pixels;
    float at(int x, int y, const std::string& channel) const {
        const int c = spec.channelindex(channel);
        EXPECT_GE(c, 0) << channel;
        return pixels[(std::size_t(y) * spec.width + x) * spec.nchannels + c];
    }
};

Exr readExr(const fs::path& path) {
    Exr e;
    auto in = OIIO::ImageInput::open(path.string());
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return e;
    e.spec = in->spec();
    e.pixels.resize(std::size_t(e.spec.width) * e.spec.height * e.spec.nchannels);
    EXPECT_TRUE(in->read_image(0, 0, 0, e.spec.nchannels, OIIO::TypeDesc::FLOAT, e.pixels.data()));
    return e;
}

std::string firstWord(const std::string& s) { return s.substr(0, s.find_first_of(" \n")); }

} // namespace

TEST(RenderExrTest, FloatChannelsZAndMetadata) {
    const fs::path scene = dir() / "plane.json", out = dir() / "plane.exr",
                   report = dir() / "plane-report.json";
    std::ofstream(scene) << kScene;
    fs::remove(out);
    const CommandResult r = runCommand(veilExe() + " render '" + scene.string() + "' -o '" +
                                       out.string() + "' --report '" + report.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const Exr exr = readExr(out);
    ASSERT_EQ(exr.spec.width, 80);
    ASSERT_EQ(exr.spec.height, 60);
    EXPECT_EQ(exr.spec.format, OIIO::TypeDesc::FLOAT);
    std::vector<std::string> names = exr.spec.channelnames;
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"A", "B", "G", "R", "Z"}));
    for (int c = 0; c < exr.spec.nchannels; ++c)
        EXPECT_EQ(exr.spec.channelformat(c), OIIO::TypeDesc::FLOAT) << c;

    // Z: the ray through each pixel centre, intersected with y = 0 in closed form. Its view
    // depth is the ray parameter for a direction whose forward component is 1.
    const glm::dvec3 eye(0, 2, 4), forward = glm::normalize(glm::dvec3(0, 1, 0) - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 1, 0)));
    const glm::dvec3 up = glm::cross(right, forward);
    const double tanHalf = std::tan(glm::radians(50.0) / 2.0), aspect = 80.0 / 60.0;
    // The far plane (200) through the float projection matrix: within 1e-4 relative.
    const float background = std::stof(exr.spec.get_string_attribute("veil:background_depth", "0"));
    EXPECT_NEAR(background, 200.0f, 0.02f);
    int plane = 0, sky = 0;
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 80; ++x) {
            const double ndcX = (x + 0.5) / 80.0 * 2.0 - 1.0, ndcY = 1.0 - (y + 0.5) / 60.0 * 2.0;
            const glm::dvec3 d =
                forward + right * (ndcX * tanHalf * aspect) + up * (ndcY * tanHalf);
            const float z = exr.at(x, y, "Z");
            EXPECT_EQ(exr.at(x, y, "A"), 1.0f);
            if (d.y >= 0.0) {
                // No opaque surface: the far plane's depth (finite, for idiff), in the header.
                EXPECT_EQ(z, background) << x << "," << y;
                ++sky;
                continue;
            }
            const double t = -eye.y / d.y;
            const glm::dvec3 hit = eye + t * d;
            if (std::abs(hit.x) > 19.0 || std::abs(hit.z) > 19.0) continue; // near the edge
            // Depth-buffer precision at t (DEPTH32F, near 0.1): far below 1e-4 t here; half
            // would be off by up to 2^-11 t.
            EXPECT_NEAR(z, t, 1e-4 * t + 1e-5) << x << "," << y;
            ++plane;
        }
    EXPECT_GT(plane, 1000);
    EXPECT_GT(sky, 100);
    // The sky is the background radiance.
    EXPECT_NEAR(exr.at(40, 0, "R"), 0.7f, 1e-3f);

    // Metadata: against sha256sum, the version the program prints, the report, glm::lookAt.
    const CommandResult sum = runCommand("sha256sum '" + scene.string() + "'");
    ASSERT_EQ(sum.exitCode, 0) << sum.output;
    EXPECT_EQ(std::string(exr.spec.get_string_attribute("veil:scene_sha256")),
              firstWord(sum.output));
    EXPECT_EQ(std::string(exr.spec.get_string_attribute("veil:scene")),
              fs::absolute(scene).string());
    const CommandResult version = runCommand(veilExe() + " --version");
    const nlohmann::json j0 = readJson(report);
    const std::string versionAttribute = exr.spec.get_string_attribute("veil:version");
    // `veil --version` adds the commit it was built from: "veil 0.1.0 (commit ...)".
    EXPECT_EQ(version.output.rfind(fmt::format("veil {}", versionAttribute), 0), 0u)
        << version.output;
    // The commit the binary was built from, as --version names it.
    const std::string commit = exr.spec.get_string_attribute("veil:commit");
    EXPECT_FALSE(commit.empty());
    EXPECT_NE(version.output.find("(commit " + commit), std::string::npos) << version.output;
    EXPECT_EQ(j0["metadata"]["veil:commit"], commit);
    EXPECT_EQ(std::string(exr.spec.get_string_attribute("veil:oit")), "blend");
    EXPECT_EQ(std::string(exr.spec.get_string_attribute("veil:camera")), "low");
    EXPECT_EQ(std::string(exr.spec.get_string_attribute("veil:size")), "80x60");
    const nlohmann::json props = nlohmann::json::parse(
        std::string(exr.spec.get_string_attribute("veil:oit_properties", "null")));
    EXPECT_TRUE(props.is_object()) << props;
    std::ifstream in(report);
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(std::string(exr.spec.get_string_attribute("veil:gl_renderer")), j["renderer"]);
    EXPECT_EQ(j["metadata"]["veil:scene_sha256"], firstWord(sum.output));
    EXPECT_EQ(j["metadata"]["veil:oit_properties"], props.dump());
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 2, 4), glm::vec3(0, 1, 0), glm::vec3(0, 1, 0));
    const OIIO::ParamValue* m =
        exr.spec.find_attribute("worldtocamera", OIIO::TypeDesc::TypeMatrix44);
    ASSERT_TRUE(m);
    const float* v = static_cast<const float*>(m->data());
    for (int i = 0; i < 16; ++i) {
        EXPECT_NEAR(v[i], (&view[0][0])[i], 1e-6) << i;
        EXPECT_NEAR(j["metadata"]["worldtocamera"][i].get<double>(), (&view[0][0])[i], 1e-6);
    }
    EXPECT_TRUE(exr.spec.find_attribute("worldtoscreen", OIIO::TypeDesc::TypeMatrix44));
}

TEST(RenderExrTest, IdenticalRendersAreEqualForOpenImageIOTools) {
    // Every channel is finite (Z of the sky is the far plane's depth), so idiff, which
    // differences every channel, finds two renders of one scene equal.
    const fs::path scene = dir() / "idiff.json", a = dir() / "idiff-a.exr",
                   b = dir() / "idiff-b.exr";
    std::ofstream(scene) << kScene;
    for (const fs::path& out : {a, b}) {
        const CommandResult r =
            runCommand(veilExe() + " render " + shellQuote(scene) + " -o " + shellQuote(out));
        ASSERT_EQ(r.exitCode, 0) << r.output;
    }
    const Exr exr = readExr(a);
    for (float v : exr.pixels)
        ASSERT_TRUE(std::isfinite(v));
    if (runCommand("command -v idiff").exitCode != 0) GTEST_SKIP() << "idiff is not installed";
    const CommandResult d = runCommand("idiff " + shellQuote(a) + " " + shellQuote(b));
    EXPECT_EQ(d.exitCode, 0) << d.output;
    EXPECT_EQ(d.output.find("inf"), std::string::npos) << d.output;
}

TEST(RenderExrTest, HalfAndFogAov) {
    nlohmann::json doc = nlohmann::json::parse(kScene);
    doc["volumes"] = {{{"procedural", "homogeneous"}, {"density_scale", 0.1}}};
    const fs::path scene = dir() / "fog.json", out = dir() / "fog.exr";
    std::ofstream(scene) << doc.dump();
    fs::remove(out);
    const CommandResult r = runCommand(veilExe() + " render '" + scene.string() + "' -o '" +
                                       out.string() + "' --half --aov fog");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const Exr exr = readExr(out);
    EXPECT_EQ(exr.spec.format, OIIO::TypeDesc::HALF);
    for (const char* c : {"R", "G", "B", "A", "Z", "fog.R", "fog.G", "fog.B", "fog.transmittance"})
        EXPECT_GE(exr.spec.channelindex(c), 0) << c;
    // Homogeneous fog over the plane: transmittance exp(-sigma * ray length) < 1, and the
    // farther pixel (top of the plane) has the lower transmittance.
    const float near = exr.at(40, 59, "fog.transmittance"),
                far = exr.at(40, 32, "fog.transmittance");
    EXPECT_GT(near, 0.0f);
    EXPECT_LT(near, 1.0f);
    EXPECT_LT(far, near);
    // Under `reference` the fog is marched piecewise and the per-pixel march is skipped unless
    // a reader asks for it: --aov fog does, so the AOV is the same march's result.
    const fs::path outRef = dir() / "fog-reference.exr";
    fs::remove(outRef);
    const CommandResult rr = runCommand(veilExe() + " render '" + scene.string() + "' -o '" +
                                        outRef.string() + "' --half --aov fog --oit reference");
    ASSERT_EQ(rr.exitCode, 0) << rr.output;
    const Exr exrRef = readExr(outRef);
    EXPECT_EQ(exrRef.at(40, 59, "fog.transmittance"), near);
    EXPECT_EQ(exrRef.at(40, 32, "fog.transmittance"), far);
    // --aov and --half need .exr; --aov fog needs fog.
    const CommandResult png = runCommand(veilExe() + " render '" + scene.string() + "' -o '" +
                                         (dir() / "fog.png").string() + "' --half");
    EXPECT_EQ(png.exitCode, 2) << png.output; // a usage error
    EXPECT_NE(png.output.find("need an .exr output"), std::string::npos) << png.output;
    std::ofstream(dir() / "plain.json") << kScene;
    const CommandResult nofog =
        runCommand(veilExe() + " render '" + (dir() / "plain.json").string() + "' -o '" +
                   (dir() / "nofog.exr").string() + "' --aov fog");
    EXPECT_EQ(nofog.exitCode, 1) << nofog.output;
    EXPECT_NE(nofog.output.find("no volumes"), std::string::npos) << nofog.output;
    EXPECT_FALSE(fs::exists(dir() / "nofog.exr"));
}

} // namespace veil::test
