// Density grids that are hard to upload (src/fog/gpu_volume.cpp): grids of
// active tiles, level sets turned into fog (interior tiles), grids wider than the GL 3D texture
// limit, index coordinates near the int32 limits, and sparse data spread far apart. Each either
// renders the analytic transmittance or ends quickly in one veil::Error giving the estimate and
// the limit.
#include "gl_fixture.h"

#include "base/error.h"
#include "fog/gpu_volume.h"
#include "frame/renderer.h"
#include "grid/density_grid.h"
#include "integrators/cpu_reference.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <nlohmann/json.hpp>
#include <openvdb/tools/LevelSetSphere.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <string>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() {
    const fs::path d = outputDir() / "fog-volume";
    fs::create_directories(d);
    return d;
}

// Orthographic camera at `eye` looking at the origin, `height` world units on size^2 pixels,
// the given grid file as the only volume.
nlohmann::json scene(const fs::path& vdb, double densityScale, nlohmann::json eye, double height,
                     double far, int size = 16) {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"ambient": 0, "tonemap": "clamp", "background": [1, 1, 1], "fog_steps": 256,
                 "fog_jitter": false},
      "cameras": [{"name": "c", "type": "orthographic", "target": [0, 0, 0], "near": 1}]})");
    doc["render"]["width"] = size;
    doc["render"]["height"] = size;
    doc["cameras"][0]["position"] = eye;
    doc["cameras"][0]["ortho_height"] = height;
    doc["cameras"][0]["far"] = far;
    doc["volumes"] = {{{"path", vdb.string()}, {"density_scale", densityScale}}};
    return doc;
}

openvdb::FloatGrid::Ptr emptyGrid(double voxelSize) {
    openvdb::initialize();
    auto g = openvdb::FloatGrid::create(0.0f);
    g->setName("density");
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    g->setTransform(openvdb::math::Transform::createLinearTransform(voxelSize));
    return g;
}

} // namespace

class FogVolumeTest : public GlTest {};

TEST_F(FogVolumeTest, TileOnlyBoxTransmittanceIsExponential) {
    // 320 x 320 x 64 voxels of density 1 stored as 8^3 tiles only (no leaf node), thickness
    // d = 64 h = 0.5 along the view, sigma = 2: T = exp(-sigma d) within 0.5%, like the slab
    // tests. Before, the brick builder found no leaf: 0 bricks and an invalid iterator.
    const double h = 0.5 / 64.0;
    auto g = emptyGrid(h);
    g->fill(openvdb::CoordBBox(openvdb::Coord(-160, -160, -32), openvdb::Coord(159, 159, 31)), 1.0f,
            true);
    ASSERT_EQ(g->tree().leafCount(), 0u);
    ASSERT_EQ(g->activeVoxelCount(), 320u * 320u * 64u);
    const fs::path p = dir() / "tiles-only.vdb";
    volume::saveGrids(p, {g});
    const scene::Scene s = scene::parseScene(scene(p, 2.0, {0, 0, 5}, 2.0, 10.0, 32), dir());
    frame::Renderer r(s, info());
    ASSERT_NE(r.fog(), nullptr);
    EXPECT_GT(r.fog()->stats().at(0).bricks, 0u);
    EXPECT_FALSE(r.fog()->stats().at(0).dense);
    r.render();
    VEIL_EXPECT_NO_GL_ERROR();
    const ImageF img = r.readHdr();
    const double expected = std::exp(-2.0 * 0.5);
    for (int y : {4, 16, 27})
        for (int x : {4, 16, 27})
            EXPECT_NEAR(img.at(x, y, 0), expected, 0.005 * expected) << x << "," << y;
}

TEST_F(FogVolumeTest, LevelSetSphereHasNoHoles) {
    // A level-set sphere (radius 0.5, 100 voxels) is converted to fog on load; sdfToFogVolume
    // fills the interior with active tiles, which the brick path dropped, leaving only the
    // narrow band. The GPU against the CPU reference over the same grid (0.005), and through the
    // centre against the chord 2R shortened by the band's linear ramp (3 voxels on each side
    // count half): exp(-sigma (2R - 3h)) within 2%.
    openvdb::initialize();
    const float h = 0.01f;
    auto ls = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(0.5f, openvdb::Vec3f(0.0f),
                                                                       h, 3.0f);
    ls->setName("density");
    const fs::path p = dir() / "level-set-sphere.vdb";
    volume::saveGrids(p, {ls});
    const nlohmann::json doc = scene(p, 1.5, {0, 0, 5}, 2.0, 10.0, 32);
    const scene::Scene s = scene::parseScene(doc, dir());
    frame::Renderer r(s, info());
    ASSERT_NE(r.fog(), nullptr);
    EXPECT_FALSE(r.fog()->stats().at(0).dense);
    r.render();
    VEIL_EXPECT_NO_GL_ERROR();
    const ImageF img = r.readHdr();
    volume::CpuFogReference ref(s, {volume::loadVolume(s.volumes[0])});
    for (int px : {16, 12, 20, 9})
        for (int py : {16, 11, 21}) {
            const volume::FogSample c = ref.pixel(s.cameras[0], 32, 32, px + 0.5, py + 0.5, 4096);
            EXPECT_NEAR(img.at(px, py, 0), c.transmittance, 0.005) << px << "," << py;
        }
    const double e = std::sqrt(2.0) * (0.5 * 2.0 / 32.0); // pixel (16, 16) off the axis
    const double chord = 2.0 * std::sqrt(0.25 - e * e) - 3.0 * h;
    EXPECT_NEAR(img.at(16, 16, 0), std::exp(-1.5 * chord), 0.02 * std::exp(-1.5 * chord));
}

TEST_F(FogVolumeTest, GridWiderThanTextureLimitIsVisible) {
    // A rod of 4 x 4 voxels and 200 voxels longer than GL_MAX_3D_TEXTURE_SIZE: small enough in
    // total for the dense path, whose texture was then too wide (GL_INVALID_VALUE, nothing
    // drawn). Seen along its axis: T = exp(-sigma L) with sigma L = 1, within 2%.
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    ASSERT_GT(max3D, 0);
    const int w = max3D + 200;
    const double h = 0.01, length = w * h;
    auto g = emptyGrid(h);
    g->transform().postTranslate(openvdb::Vec3d(0.5 * h)); // voxel centres at (i + 0.5) h
    g->denseFill(openvdb::CoordBBox(openvdb::Coord(0, -2, -2), openvdb::Coord(w - 1, 1, 1)), 1.0f,
                 true);
    const fs::path p = dir() / "wide-rod.vdb";
    volume::saveGrids(p, {g});
    const scene::Scene s = scene::parseScene(
        scene(p, 1.0 / length, {length + 2.0, 0, 0}, 0.08, length + 5.0, 16), dir());
    frame::Renderer r(s, info());
    VEIL_EXPECT_NO_GL_ERROR();
    ASSERT_NE(r.fog(), nullptr);
    const volume::GpuVolumeStats st = r.fog()->stats().at(0);
    EXPECT_FALSE(st.dense);
    r.render();
    VEIL_EXPECT_NO_GL_ERROR();
    const ImageF img = r.readHdr();
    EXPECT_NEAR(img.at(8, 8, 0), std::exp(-1.0), 0.02 * std::exp(-1.0));
    EXPECT_NEAR(img.at(1, 1, 0), 1.0, 1e-3); // beside the rod
}

TEST_F(FogVolumeTest, HugeTileGridIsCoarsenedQuickly) {
    // 1016^3 = 1.05e9 voxels of tiles against a 64 MiB budget: coarsened three times. Through
    // tools::resampleToMatch the first coarsening alone took 15.7 s (tiles sampled voxel by
    // voxel). Coarsening box-filters, so the interior keeps density 1.
    auto g = emptyGrid(0.001);
    g->fill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(1015)), 1.0f, true);
    volume::GpuVolumeOptions options;
    options.budgetBytes = std::size_t(64) << 20;
    const auto t0 = std::chrono::steady_clock::now();
    volume::GpuVolume v(g, glm::mat4(1.0f), options);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_LT(seconds, 5.0 * test::kSlowBuildFactor);
    EXPECT_GE(v.stats().coarsened, 3);
    EXPECT_LE(v.stats().gpuBytes, options.budgetBytes);
    EXPECT_EQ(v.stats().activeVoxels, 127u * 127u * 127u);
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(FogVolumeTest, IndexCoordinatesNearInt32LimitsAreRefused) {
    // The span of these two voxels overflowed the int32 size estimate.
    auto g = emptyGrid(1.0);
    g->tree().setValue(openvdb::Coord(-2147483000, 0, 0), 1.0f);
    g->tree().setValue(openvdb::Coord(2147483000, 0, 0), 1.0f);
    const std::string msg = errorOf([&] { volume::GpuVolume v(g, glm::mat4(1.0f)); });
    EXPECT_NE(msg.find("index coordinates"), std::string::npos) << msg;
    EXPECT_NE(msg.find("2147483000"), std::string::npos) << msg;
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(FogVolumeTest, FarApartVoxelsFinishQuicklyCoarsenedOrRefused) {
    // Two voxels 1e4 voxels apart on each axis: the indirection table over their leaves had 2e9
    // entries; coarsened once it was 940 MiB, inside the 1 GiB budget, and took over 120 s.
    auto g = emptyGrid(0.001);
    g->tree().setValue(openvdb::Coord(0, 0, 0), 1.0f);
    g->tree().setValue(openvdb::Coord(10000, 10000, 10000), 1.0f);
    const auto t0 = std::chrono::steady_clock::now();
    volume::GpuVolume v(g, glm::mat4(1.0f));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_LT(seconds, 5.0);
    EXPECT_GE(v.stats().coarsened, 1);
    EXPECT_LE(v.stats().gpuBytes, std::size_t(160) << 20);
    VEIL_EXPECT_NO_GL_ERROR();
    volume::GpuVolumeOptions refuse;
    refuse.refuseOverBudget = true;
    const std::string msg = errorOf([&] { volume::GpuVolume r(g, glm::mat4(1.0f), refuse); });
    EXPECT_NE(msg.find("indirection table"), std::string::npos) << msg;
    EXPECT_NE(msg.find("over the limit"), std::string::npos) << msg;
}

TEST_F(FogVolumeTest, VdbThatCrashesOpenVdbIsOneClearCliError) {
    // torus01.vdb with 64 random bytes (the 19th overwrite of mt19937 seed 7, as in
    // VolumeTest.DamagedVdbFilesLoadOrFailNamingTheFile): OpenVDB's reader corrupts the heap and
    // `veil render` died with "free(): invalid pointer" (exit 134). The trial read in a child
    // turns that into one line and exit code 1.
    std::ifstream in(dataDir() / "vdb-torus-fog/torus01.vdb", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    ASSERT_GT(bytes.size(), 10000u);
    std::mt19937 rng(7);
    const std::size_t size = bytes.size();
    for (int k = 0; k <= 18; ++k) {
        const std::size_t at = 200 + rng() % (size - 264);
        for (std::size_t j = 0; j < 64; ++j) {
            const char c = char(rng() & 0xFF);
            if (k == 18) bytes[at + j] = c;
        }
    }
    const fs::path d = dir() / "cli-crash";
    fs::create_directories(d);
    std::ofstream(d / "heap-crash.vdb", std::ios::binary) << bytes;
    nlohmann::json doc = scene(d / "heap-crash.vdb", 1.0, {0, 0, 30}, 20.0, 60.0);
    doc["volumes"][0]["grid"] = "voxel_fog_density";
    std::ofstream(d / "scene.json") << doc.dump();
    const fs::path out = d / "out.png";
    fs::remove(out);
    const CommandResult r = runCommand(veilExe() + " render '" + (d / "scene.json").string() +
                                       "' -o '" + out.string() + "'");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("heap-crash.vdb"), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

namespace {

// The texels [0, size) of a 3D texture, as floats (R32UI tables as unsigned integers).
std::vector<float> texels(const gpu::Texture& t, const glm::ivec3& size, int components,
                          bool integer = false) {
    std::vector<float> out(std::size_t(size.x) * size.y * size.z * components);
    glGetTextureSubImage(t.id(), 0, 0, 0, 0, size.x, size.y, size.z,
                         integer ? GL_RED_INTEGER : (components == 4 ? GL_RGBA : GL_RED),
                         integer ? GL_UNSIGNED_INT : GL_FLOAT, GLsizei(out.size() * 4), out.data());
    return out;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * 4) == 0;
}

} // namespace

// Two frames of a growing block of bricks (11 and 13 leaves high: atlases of 11 and 12 layers of
// bricks, indirection tables of 12 and 14 leaves) round to the same allocation: replace() keeps
// the three textures (their GL names) and they then hold what a volume made for the second
// frame alone holds; a frame of another size (the same data as a dense box) gets textures of
// its own size. Mutation: replace() re-creating the textures as the constructor does -> the
// names change (the upload into new textures every frame that cost 7.8 ms of the H100's
// 28.3 ms a frame at 1920x1080).
TEST_F(FogVolumeTest, ReplacedFrameKeepsTexturesThatFit) {
    auto frame = [](int leavesHigh, std::size_t denseLimit) {
        auto density = emptyGrid(0.01), heat = emptyGrid(0.01);
        auto d = density->getAccessor(), h = heat->getAccessor();
        for (int z = 0; z < 8 * leavesHigh; ++z)
            for (int y = 0; y < 80; ++y)
                for (int x = 0; x < 80; ++x) {
                    d.setValue({x, y, z}, float((x * 7 + y * 3 + z) % 13 + 1) / 13.0f);
                    h.setValue({x, y, z}, float((x + y * 5 + z * 11) % 17) / 17.0f);
                }
        volume::GpuVolumeOptions options;
        options.denseVoxelLimit = denseLimit;
        volume::GridConversion c = volume::convertGrid(*density, options, 2048);
        volume::addChannel(c, {heat});
        return c;
    };
    const volume::GridConversion a = frame(11, 0), b = frame(13, 0);
    ASSERT_FALSE(b.stats.dense);
    ASSERT_NE(a.dataSize, b.dataSize);
    ASSERT_NE(a.tableSize, b.tableSize);
    volume::GpuVolume v(a, glm::mat4(1.0f));
    const GLuint data = v.data().id(), channel = v.channel().id(), table = v.indirection().id();
    v.replace(b, glm::mat4(1.0f));
    EXPECT_EQ(v.data().id(), data);
    EXPECT_EQ(v.channel().id(), channel);
    EXPECT_EQ(v.indirection().id(), table);
    auto expectAsAlone = [&](const volume::GpuVolume& got, const volume::GridConversion& c) {
        const volume::GpuVolume alone(c, glm::mat4(1.0f));
        EXPECT_EQ(got.data().width(), alone.data().width());
        EXPECT_EQ(got.data().depth(), alone.data().depth());
        EXPECT_TRUE(
            sameBits(texels(got.data(), c.dataSize, 1), texels(alone.data(), c.dataSize, 1)));
        EXPECT_TRUE(
            sameBits(texels(got.channel(), c.dataSize, 1), texels(alone.channel(), c.dataSize, 1)));
        if (!c.stats.dense) {
            EXPECT_TRUE(sameBits(texels(got.indirection(), c.tableSize, 1, true),
                                 texels(alone.indirection(), c.tableSize, 1, true)));
        }
        EXPECT_EQ(got.indexMax(), alone.indexMax());
        EXPECT_EQ(got.bricksPerAxis(), alone.bricksPerAxis());
    };
    expectAsAlone(v, b);
    // Another size (the same frame as a dense box): textures of that size.
    const volume::GridConversion dense = frame(13, std::size_t(1) << 24);
    ASSERT_TRUE(dense.stats.dense);
    v.replace(dense, glm::mat4(1.0f));
    EXPECT_FALSE(v.indirection());
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    EXPECT_EQ(v.data().depth(), volume::GpuVolume::allocatedSize(dense.dataSize, false, max3D).z);
    expectAsAlone(v, dense);
    VEIL_EXPECT_NO_GL_ERROR();
}

// The texels are converted to half floats on the CPU (F16C or Imath, round to nearest even) and
// uploaded as GL_HALF_FLOAT: bit for bit what the driver makes of the same floats uploaded as
// GL_FLOAT, ties, half subnormals, the largest half and past it included. Mutation: the
// conversion truncating (_MM_FROUND_TO_ZERO) -> the ties and most random values differ.
TEST_F(FogVolumeTest, HalfFloatTexelsEqualTheDriversConversion) {
    std::vector<float> values = {0.0f,
                                 1.0f + 1.0f / 2048.0f,
                                 1.0f + 3.0f / 2048.0f,
                                 1e-6f,
                                 6e-8f,
                                 3e-8f,
                                 65504.0f,
                                 65519.0f,
                                 65520.0f,
                                 0.1f,
                                 1.0f / 3.0f,
                                 2049.0f,
                                 2051.0f,
                                 1e-5f,
                                 6.1e-5f,
                                 6.09e-5f};
    std::mt19937 random(7);
    std::uniform_real_distribution<float> exponent(-20.0f, 15.0f);
    while (values.size() < 4096)
        values.push_back(std::exp2(exponent(random)) * (1.0f + float(values.size() % 97) / 97.0f));
    volume::GridConversion c;
    c.stats.dense = true;
    c.dataSize = glm::ivec3(16, 16, 16);
    c.values = values;
    c.channel = values;
    c.channelComponents = 1;
    c.indexMax = glm::vec3(16.0f);
    const volume::GpuVolume v(c, glm::mat4(1.0f));
    const gpu::Texture driver =
        volume::makeFilteredTexture3D(c.dataSize, GL_R16F, GL_RED, values.data());
    const std::vector<float> expected = texels(driver, c.dataSize, 1);
    EXPECT_TRUE(sameBits(texels(v.data(), c.dataSize, 1), expected));
    EXPECT_TRUE(sameBits(texels(v.channel(), c.dataSize, 1), expected));
    EXPECT_EQ(expected[1], 1.0f);                  // a tie to the even neighbour
    EXPECT_EQ(expected[2], 1.0f + 4.0f / 2048.0f); // and up to it
    EXPECT_TRUE(std::isinf(expected[8]));
    VEIL_EXPECT_NO_GL_ERROR();
}

} // namespace veil::test
