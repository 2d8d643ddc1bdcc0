// `veil voxelize mesh.obj|.ply` without a scene and `veil info file.vdb` per grid,
// checked against bounds read from the OBJ text and values read through OpenVDB.
#include "support/test_support.h"
#include "support/vdb_read.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <fstream>
#include <sstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() { return outputSubdir("voxelize_mesh_info"); }

} // namespace

TEST(VoxelizeMeshTest, ObjGetsCubicVoxelsFittedToItsBounds) {
    // The teapot's bounds from its "v x y z" lines, independent of the mesh loader.
    std::ifstream obj(dataDir() / "utah-teapot" / "teapot.obj");
    std::string line;
    openvdb::Vec3d lo(1e300), hi(-1e300);
    while (std::getline(obj, line))
        if (line.rfind("v ", 0) == 0) {
            std::istringstream in(line.substr(2));
            openvdb::Vec3d v;
            in >> v[0] >> v[1] >> v[2];
            lo = openvdb::math::minComponent(lo, v);
            hi = openvdb::math::maxComponent(hi, v);
        }
    const openvdb::Vec3d e = hi - lo;
    const double voxel = std::max({e[0], e[1], e[2]}) * 1.06 / 32.0;
    const fs::path out = dir() / "teapot.vdb";
    fs::remove(out);
    const CommandResult r =
        runCommand(veilExe() + " voxelize " + shellQuote(dataDir() / "utah-teapot" / "teapot.obj") +
                   " --res 32 -o " + shellQuote(out));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto grids = readVdbGrids(out);
    const openvdb::GridBase::Ptr density = grids->at(0);
    EXPECT_EQ(density->getName(), "density");
    const openvdb::Vec3d vs = density->voxelSize();
    for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(vs[a], voxel, 1e-6 * voxel) << a; // cubic, and --res along the longest
    const openvdb::BBoxd world =
        density->transform().indexToWorld(density->evalActiveVoxelBoundingBox());
    for (int a = 0; a < 3; ++a) {
        // Surface voxels hold the extreme vertices: the active box reaches the bounds within
        // a voxel, and the fitted grid is no larger than the bounds + 6% + one voxel.
        EXPECT_LE(world.min()[a], lo[a] + voxel) << a;
        EXPECT_GE(world.min()[a], lo[a] - voxel) << a;
        EXPECT_GE(world.max()[a], hi[a] - voxel) << a;
        EXPECT_LE(world.max()[a], hi[a] + voxel) << a;
    }
    const openvdb::Coord dim = density->evalActiveVoxelBoundingBox().dim();
    EXPECT_LT(dim.y(), 32); // fitted, not a res^3 cube
}

TEST(VoxelizeMeshTest, FlatPlyIsOneSliceAndBadMeshIsNamed) {
    const fs::path ply = dir() / "quad.ply";
    std::ofstream(ply) << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                          "property float y\nproperty float z\nelement face 2\n"
                          "property list uchar int vertex_indices\nend_header\n"
                          "0 0 0\n2 0 0\n2 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
    const fs::path out = dir() / "quad.vdb";
    CommandResult r =
        runCommand(veilExe() + " voxelize " + shellQuote(ply) + " --res 16 -o " + shellQuote(out));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("16x8x1"), std::string::npos) << r.output;
    const auto grids = readVdbGrids(out);
    const openvdb::CoordBBox box = grids->at(0)->evalActiveVoxelBoundingBox();
    EXPECT_EQ(box.dim().z(), 1);
    EXPECT_EQ(box.dim().x(), 16);

    const fs::path broken = dir() / "broken.obj";
    std::ofstream(broken) << "v 0 0 0\nf 1 2 3\n";
    r = runCommand(veilExe() + " voxelize " + shellQuote(broken) + " -o " +
                   shellQuote(dir() / "broken.vdb"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("broken.obj"), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(dir() / "broken.vdb"));
    r = runCommand(veilExe() + " voxelize " + shellQuote(ply) + " --perspective -o " +
                   shellQuote(out));
    EXPECT_EQ(r.exitCode, 2) << r.output; // a usage error
    EXPECT_NE(r.output.find("need a scene file"), std::string::npos) << r.output;
}

TEST(InfoVdbTest, EveryGridWithRangeAndMetadataSelectableByNameAndIndex) {
    const fs::path smoke = dataDir() / "vdb-smoke" / "smoke.vdb";
    CommandResult r = runCommand(veilExe() + " info " + shellQuote(smoke));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // The range, computed here over the active values.
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(readVdbGrids(smoke)->at(0));
    float lo = 1e30f, hi = -1e30f;
    for (auto it = grid->cbeginValueOn(); it; ++it)
        lo = std::min(lo, *it), hi = std::max(hi, *it);
    EXPECT_NE(r.output.find(fmt::format("0 'density' float (fog volume): 1049275 active voxels, "
                                        "min {:.6g}, max {:.6g}",
                                        lo, hi)),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("voxel size (0.4762 0.4762 0.4762)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("is_saved_as_half_float: bool = true"), std::string::npos) << r.output;

    // Three grids of one name: an index reaches each, the name the first.
    const fs::path three = dataDir() / "vdb-three-density-grids" / "grids.vdb";
    for (const auto& [selector, expect] :
         std::vector<std::pair<std::string, std::string>>{{"1", "1 'density' float"},
                                                          {"2", "2 'density' float"},
                                                          {"density", "0 'density' float"}}) {
        r = runCommand(veilExe() + " info " + shellQuote(three) + " --grid " + selector);
        ASSERT_EQ(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find(expect), std::string::npos) << selector << "\n" << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\''), 2) << r.output; // one grid
    }
    r = runCommand(veilExe() + " info " + shellQuote(three) + " --grid 1");
    EXPECT_NE(r.output.find("2222 active voxels"), std::string::npos) << r.output;
    r = runCommand(veilExe() + " info " + shellQuote(three) + " --grid 3");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("grids.vdb' has no grid 3 (3 grids"), std::string::npos) << r.output;
}

} // namespace veil::test
