// Slice map -> .vdb -> openvdb::io::File read back: same voxels at the same world positions;
// .vti -> vtkXMLImageDataReader (io::readVti): same dimensions, origin, spacing and values.
// Inputs come from the CPU reference voxelizer, so no GL is needed.
#include "base/error.h"
#include "io/vtk_export.h"
#include "scene/mesh.h"
#include "support/test_support.h"
#include "voxelize/cpu_voxelizer.h"
#include "voxelize/vdb_convert.h"

#include <gtest/gtest.h>
#include <openvdb/io/File.h>

namespace veil::voxelize {
namespace {

TEST(VoxelizeExportTest, VdbRoundTripKeepsVoxelsAndWorldPositions) {
    const Triangles tris = fromMesh(scene::makeTorus(1.0f, 0.3f, 32, 16));
    // Non-cubic cells and an off-origin box so a wrong transform shows.
    SliceMap map = makeOrthoGrid({-1.4, -1.5, -0.4}, {1.6, 1.3, 0.5}, 40, 36, 20);
    voxelizeSurfaceCpu(tris, map);
    ASSERT_TRUE(isLatticeGrid(map));
    const VdbGrids grids = toVdb(map);
    EXPECT_EQ(grids.mask->activeVoxelCount(), map.countSet());
    const auto path = test::outputDir() / "voxelize-roundtrip.vdb";
    writeVdb(path, grids);

    openvdb::io::File file(path.string());
    file.open();
    auto base = file.readGrid("mask");
    auto dens = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
    file.close();
    auto mask = openvdb::gridPtrCast<openvdb::BoolGrid>(base);
    ASSERT_TRUE(mask && dens);
    EXPECT_EQ(mask->activeVoxelCount(), map.countSet());
    EXPECT_EQ(dens->activeVoxelCount(), map.countSet());
    std::uint64_t checked = 0;
    for (auto it = mask->cbeginValueOn(); it; ++it) {
        const openvdb::Vec3d w = mask->indexToWorld(it.getCoord());
        int x, y, s;
        ASSERT_TRUE(map.locate({w.x(), w.y(), w.z()}, x, y, s));
        EXPECT_TRUE(map.get(x, y, s));
        const glm::dvec3 c = map.cellCenter(x, y, s);
        EXPECT_NEAR(glm::length(c - glm::dvec3(w.x(), w.y(), w.z())), 0.0, 1e-9);
        EXPECT_EQ(dens->tree().getValue(it.getCoord()), 1.0f);
        ++checked;
    }
    EXPECT_EQ(checked, map.countSet());
}

TEST(VoxelizeExportTest, SmoothedDensityIsSoftAndBounded) {
    SliceMap map = makeOrthoGrid({-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}, 32, 32, 32);
    voxelizeSolidCpu(fromMesh(scene::makeSphere(1.0f, 32, 16)), map);
    VdbOptions o;
    o.smoothing = 1.0;
    const VdbGrids g = toVdb(map, o);
    float lo = 1.0f, hi = 0.0f;
    for (auto it = g.density->cbeginValueOn(); it; ++it)
        lo = std::min(lo, *it), hi = std::max(hi, *it);
    EXPECT_GE(lo, 0.0f);
    EXPECT_LE(hi, 1.0f + 1e-5f);
    EXPECT_GT(hi, 0.99f); // the sphere's core stays dense
    EXPECT_GT(g.density->activeVoxelCount(), g.mask->activeVoxelCount()); // soft rim added
    EXPECT_NEAR(g.density->tree().getValue(openvdb::Coord(16, 16, 16)), 1.0f, 1e-5f);
}

TEST(VoxelizeExportTest, VtiRoundTrip) {
    io::DenseGrid g;
    g.dims = {5, 4, 3};
    g.origin = {-1.5, 0.25, 2.0};
    g.spacing = {0.5, 0.25, 0.125};
    for (int i = 0; i < 60; ++i)
        g.values.push_back(float(i % 7) * 0.25f);
    const auto path = test::outputDir() / "voxelize-roundtrip.vti";
    io::writeVti(path, g);
    const io::DenseGrid r = io::readVti(path);
    EXPECT_EQ(r.dims, g.dims);
    for (int i = 0; i < 3; ++i) {
        EXPECT_DOUBLE_EQ(r.origin[i], g.origin[i]);
        EXPECT_DOUBLE_EQ(r.spacing[i], g.spacing[i]);
    }
    EXPECT_EQ(r.values, g.values);
    EXPECT_EQ(r.name, "density");
    EXPECT_THROW(io::writeVti(test::outputDir() / "no-such-dir" / "x.vti", g), Error);
    EXPECT_FALSE(std::filesystem::exists(test::outputDir() / "no-such-dir"));
}

} // namespace
} // namespace veil::voxelize
