// `veil render --dump DIR`: every frame resource of a scene with a volume
// and a shadowed spot light, read back through OpenImageIO and VTK and checked against the
// frame's own EXR (same frame, same values).
#include "capture/dump.h"
#include "io/vtk_export.h"
#include "support/test_support.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataReader.h>

#include <cmath>
#include <fstream>
#include <map>
#include <set>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

struct Exr {
    OIIO::ImageSpec spec;
    std::vector<float> pixels;
};

Exr readExr(const fs::path& path) {
    Exr e;
    auto in = OIIO::ImageInput::open(path.string());
    EXPECT_TRUE(in) << path << ": " << OIIO::geterror();
    if (!in) return e;
    e.spec = in->spec();
    e.pixels.resize(std::size_t(e.spec.width) * e.spec.height * e.spec.nchannels);
    EXPECT_TRUE(in->read_image(0, 0, 0, e.spec.nchannels, OIIO::TypeDesc::FLOAT, e.pixels.data()));
    return e;
}

const char* kScene = R"({
  "render": {"width": 72, "height": 64, "shadow_map_size": 128},
  "cameras": [{"name": "c", "position": [0, 1.5, 4], "target": [0, 0, 0]}],
  "lights": [{"type": "spot", "position": [1, 4, 1], "target": [0, 0, 0], "intensity": 30}],
  "materials": {"m": {"base_color": 0.5}},
  "objects": [{"shape": {"type": "box", "size": [1, 1, 1]}, "material": "m",
               "transform": {"translate": [0.8, 0.5, 0]}},
              {"shape": {"type": "plane", "size": [3, 3]}, "material": "m"}],
  "volumes": [{"procedural": "sphere", "size": 1.2, "voxel_size": 0.05, "density_scale": 3,
               "transform": {"translate": [-0.6, 0.7, 0]}}]
})";

} // namespace

TEST(DumpTest, EveryResourceWithManifest) {
    const fs::path d = outputDir() / "dump";
    fs::remove_all(d);
    fs::create_directories(d);
    const fs::path scene = d / "scene.json", out = d / "frame.exr", dumpDir = d / "resources";
    std::ofstream(scene) << kScene;
    const CommandResult r = runCommand(veilExe() + " render '" + scene.string() + "' -o '" +
                                       out.string() + "' --dump '" + dumpDir.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::ifstream in(dumpDir / "manifest.json");
    const nlohmann::json manifest = nlohmann::json::parse(in);
    std::set<std::string> names, files{"manifest.json"};
    for (const auto& e : manifest["resources"]) {
        names.insert(e["resource"].get<std::string>());
        if (!e["dumpable"].get<bool>()) {
            EXPECT_FALSE(e["reason"].get<std::string>().empty()) << e;
            continue;
        }
        if (e.contains("files"))
            for (const auto& f : e["files"])
                files.insert(f.get<std::string>());
        else
            files.insert(e["file"].get<std::string>());
        EXPECT_FALSE(e["units"].get<std::string>().empty()) << e;
        EXPECT_FALSE(e["format"].get<std::string>().empty()) << e;
    }
    EXPECT_EQ(names,
              (std::set<std::string>{"shadow.depth", "depth", "hdr", "fog.light_transmittance",
                                     "fog.radiance", "oit.accumulation", "ldr"}));
    std::set<std::string> present;
    for (const auto& e : fs::directory_iterator(dumpDir))
        present.insert(e.path().filename().string());
    EXPECT_EQ(present, files); // nothing unlisted, nothing missing, no temporaries
    for (const auto& e : manifest["resources"])
        if (e["resource"] == "oit.accumulation") {
            EXPECT_FALSE(e["dumpable"].get<bool>());
            EXPECT_NE(e["reason"].get<std::string>().find("blend"), std::string::npos) << e;
        }

    // The frame's own EXR: R, G, B and Z.
    const Exr frame = readExr(out);
    ASSERT_EQ(frame.spec.width, 72);
    const int zc = frame.spec.channelindex("Z");
    ASSERT_GE(zc, 0);
    const Exr hdr = readExr(dumpDir / "hdr.exr"), depth = readExr(dumpDir / "depth.exr");
    EXPECT_EQ(hdr.spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(depth.spec.format, OIIO::TypeDesc::FLOAT);
    ASSERT_EQ(hdr.spec.width, 72);
    ASSERT_EQ(hdr.spec.height, 64);
    ASSERT_EQ(depth.spec.nchannels, 1);
    ASSERT_EQ(depth.spec.width * depth.spec.height, 72 * 64);
    // Depth (window, nonlinear) turned into view depth with the default near 0.05, far 100:
    // z = 2 n f / (f + n - (2 d - 1)(f - n)); the frame's Z is the same quantity.
    const double n = 0.05, f = 100.0;
    int surfaces = 0, empty = 0;
    for (int p = 0; p < 72 * 64; ++p) {
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(hdr.pixels[p * 4 + c], frame.pixels[p * frame.spec.nchannels + c]) << p;
        const double dw = depth.pixels[p];
        const float z = frame.pixels[p * frame.spec.nchannels + zc];
        if (dw >= 1.0) {
            EXPECT_NEAR(z, f, 1e-4 * f) << p; // no surface: the far plane's depth
            ++empty;
            continue;
        }
        const double view = 2.0 * n * f / (f + n - (2.0 * dw - 1.0) * (f - n));
        EXPECT_NEAR(z, view, 1e-4 * view) << p;
        ++surfaces;
    }
    EXPECT_GT(surfaces, 500);
    EXPECT_GT(empty, 500);

    // The shadow map sees the casters (depth < 1) and nothing beyond [0, 1].
    const Exr shadow = readExr(dumpDir / "shadow.depth.layer0.exr");
    EXPECT_EQ(shadow.spec.width, 128);
    const auto [lo, hi] = std::minmax_element(shadow.pixels.begin(), shadow.pixels.end());
    EXPECT_GE(*lo, 0.0f);
    EXPECT_LT(*lo, 0.999f);
    EXPECT_LE(*hi, 1.0f);

    // The light-space transmittance volume: a 3D grid through VTK's reader, values in (0, 1]
    // with the ball absorbing (density 3 over up to 1.2 units: T down to exp(-3.6)).
    vtkNew<vtkXMLImageDataReader> reader;
    reader->SetFileName((dumpDir / "fog.light_transmittance.vti").string().c_str());
    reader->Update();
    vtkImageData* vol = reader->GetOutput();
    int dims[3];
    vol->GetDimensions(dims);
    for (const auto& e : manifest["resources"])
        if (e["resource"] == "fog.light_transmittance") {
            EXPECT_EQ(dims[0], e["width"].get<int>());
            EXPECT_EQ(dims[1], e["height"].get<int>());
            EXPECT_EQ(dims[2], e["depth"].get<int>());
        }
    EXPECT_GT(dims[2], 1);
    double range[2];
    vol->GetPointData()->GetArray(0)->GetRange(range);
    EXPECT_GT(range[0], 0.0);
    EXPECT_LT(range[0], 0.5);
    EXPECT_LE(range[1], 1.0 + 1e-3);
    // Its field data names what it is (as the EXR dumps' header attributes do).
    const io::DenseGrid back = io::readVti(dumpDir / "fog.light_transmittance.vti");
    const std::map<std::string, std::string> field(back.fieldData.begin(), back.fieldData.end());
    EXPECT_EQ(field.count("veil_resource") ? field.at("veil_resource") : "",
              "fog.light_transmittance");
    for (const auto& e : manifest["resources"])
        if (e["resource"] == "fog.light_transmittance") {
            EXPECT_EQ(field.count("veil_format") ? field.at("veil_format") : "",
                      e["format"].get<std::string>());
        }
    EXPECT_EQ(field.count("veil_units") ? field.at("veil_units") : "",
              capture::resourceUnits("fog.light_transmittance"));
}

TEST(DumpTest, DumpIntoAFileIsRefused) {
    const fs::path d = outputDir() / "dump-refused";
    fs::create_directories(d);
    std::ofstream(d / "scene.json") << kScene;
    std::ofstream(d / "afile") << "x";
    const CommandResult r =
        runCommand(veilExe() + " render '" + (d / "scene.json").string() + "' -o '" +
                   (d / "o.png").string() + "' --dump '" + (d / "afile").string() + "'");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("afile': exists and is not a folder"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(d / "o.png"));
}

} // namespace veil::test
