// `veil voxelize` end to end: a scene to .vdb + .vti with the summary; bad --method, a
// missing scene and an unwritable output end in one clear line, a non-zero exit and no file.
#include "io/vtk_export.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <map>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() {
    const fs::path d = outputDir() / "voxelize-cli";
    fs::create_directories(d);
    return d;
}

fs::path scene() {
    const fs::path p = dir() / "scene.json";
    std::ofstream(p) << R"({
  "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0, 0]}],
  "materials": {"m": {"base_color": 0.5}},
  "objects": [{"shape": {"type": "sphere", "radius": 1}, "material": "m"},
              {"shape": {"type": "box", "size": [0.5, 0.5, 0.5]}, "material": "m",
               "transform": {"translate": [2, 0, 0]}}]
})";
    return p;
}

void expectFails(const std::string& args, const fs::path& out, const std::string& says) {
    fs::remove(out);
    const CommandResult r = runCommand(veilExe() + " voxelize " + args + " 2>&1");
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_FALSE(fs::exists(out)) << out;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find("veil: error:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(says), std::string::npos) << r.output;
}

} // namespace

TEST(VoxelizeCliTest, WritesVdbAndVtiWithSummary) {
    const fs::path vdb = dir() / "grid.vdb", vti = dir() / "grid.vti";
    fs::remove(vdb);
    fs::remove(vti);
    const CommandResult r =
        runCommand(veilExe() + " voxelize '" + scene().string() + "' --res 48 --slices 40 -o '" +
                   vdb.string() + "' --vti '" + vti.string() + "' 2>&1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("method: conservative"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(" set ("), std::string::npos) << r.output;
    openvdb::initialize();
    openvdb::io::File file(vdb.string());
    file.open();
    auto grid = file.readGrid("density");
    file.close();
    EXPECT_GT(grid->activeVoxelCount(), 1000u);
    const io::DenseGrid d = io::readVti(vti);
    EXPECT_EQ(d.dims, (std::array<int, 3>{48, 48, 40}));
    const auto on = std::count(d.values.begin(), d.values.end(), 1.0f);
    EXPECT_EQ(static_cast<openvdb::Index64>(on), grid->activeVoxelCount());
    // The .vdb's mask grid is in the .vti too, voxel for voxel.
    file.open();
    auto mask = openvdb::gridPtrCast<openvdb::BoolGrid>(file.readGrid("mask"));
    file.close();
    ASSERT_TRUE(mask);
    ASSERT_EQ(d.moreScalars.size(), 1u);
    EXPECT_EQ(d.moreScalars[0].first, "mask");
    const std::vector<float>& m = d.moreScalars[0].second;
    ASSERT_EQ(m.size(), d.values.size());
    std::size_t agree = 0;
    for (auto it = mask->cbeginValueOn(); it; ++it) {
        const openvdb::Coord c = it.getCoord();
        agree += m[(std::size_t(c.z()) * 48 + c.y()) * 48 + c.x()] == 1.0f;
    }
    EXPECT_EQ(agree, mask->activeVoxelCount());
    EXPECT_EQ(std::count(m.begin(), m.end(), 1.0f), std::ptrdiff_t(mask->activeVoxelCount()));
    // Where it came from, as field data.
    std::map<std::string, std::string> field(d.fieldData.begin(), d.fieldData.end());
    EXPECT_EQ(field["veil_source"], scene().string());
    EXPECT_NE(field["veil_command"].find(" voxelize "), std::string::npos);
    EXPECT_NE(field["veil_command"].find("--res 48 --slices 40"), std::string::npos);
    EXPECT_EQ(field["veil_version"].rfind("0.", 0), 0u) << field["veil_version"];
    EXPECT_NE(field["veil_version"].find("(commit "), std::string::npos);
    EXPECT_NE(field["veil_grids"].find("density, mask"), std::string::npos);
}

TEST(VoxelizeCliTest, ThirdPartyTeapotToVdbAndVtiReadBack) {
    // The issue's acceptance: the third-party mesh through `veil voxelize` into a .vdb and a
    // .vti that read back with the same voxels, inside the mesh's bounds.
    const fs::path teapot = dataDir() / "utah-teapot/teapot.obj";
    ASSERT_TRUE(fs::exists(teapot)) << teapot;
    const fs::path sc = dir() / "teapot.json";
    std::ofstream(sc) << R"({"cameras": [{"position": [0, 1, 3], "target": [0, 0, 0]}],
      "objects": [{"mesh": ")"
                      << teapot.string() << R"("}]})";
    const fs::path vdb = dir() / "teapot.vdb", vti = dir() / "teapot.vti";
    fs::remove(vdb);
    fs::remove(vti);
    const CommandResult r = runCommand(veilExe() + " voxelize '" + sc.string() +
                                       "' --res 64 --method compute --quiet -o '" + vdb.string() +
                                       "' --vti '" + vti.string() + "' 2>&1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    openvdb::initialize();
    openvdb::io::File file(vdb.string());
    file.open();
    auto grid = file.readGrid("density");
    file.close();
    EXPECT_GT(grid->activeVoxelCount(), 2000u);
    // Teapot bounds (-0.5, -0.245, -0.311)..(0.5, 0.245, 0.311), plus one voxel.
    const openvdb::BBoxd wb = grid->transform().indexToWorld(grid->evalActiveVoxelBoundingBox());
    const double v = grid->voxelSize().x();
    EXPECT_NEAR(wb.min().x(), -0.5, 1.5 * v);
    EXPECT_NEAR(wb.max().x(), 0.5, 1.5 * v);
    EXPECT_NEAR(wb.max().y(), 0.245, 1.5 * v);
    const io::DenseGrid d = io::readVti(vti);
    const auto on = std::count(d.values.begin(), d.values.end(), 1.0f);
    EXPECT_EQ(static_cast<openvdb::Index64>(on), grid->activeVoxelCount());
}

TEST(VoxelizeCliTest, BadInputFailsCleanly) {
    const fs::path out = dir() / "bad.vdb";
    const std::string s = "'" + scene().string() + "'";
    expectFails(s + " --method splat -o '" + out.string() + "'", out,
                "unknown voxelization method");
    expectFails("'" + (dir() / "missing.json").string() + "' -o '" + out.string() + "'", out,
                "missing.json");
    const fs::path unwritable = dir() / "no-such-dir" / "x.vdb";
    expectFails(s + " -o '" + unwritable.string() + "'", unwritable, "does not exist");
    expectFails(s + " --method compute --solid -o '" + out.string() + "'", out, "solid");
}

} // namespace veil::test
