// `veil render file.vdb` frames the grid: the corners of the grid's active bounding box,
// projected through the default camera's own matrices, stay inside the image and span at
// least 85% of its (square) side on the wider axis, centred; a bare render used to leave
// about two thirds of the frame empty (the bounding sphere was fitted, not the box).
#include "grid/vdb_file.h"
#include "grid/vdb_scene.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cstdio>

namespace veil::test {

namespace {

// The projected bounds of the grid's active voxels (cell extents) in normalised device
// coordinates of a square image: {min x, min y, max x, max y}.
std::array<double, 4> projectedBounds(const std::filesystem::path& vdb,
                                      const scene::Camera& camera) {
    const openvdb::GridPtrVecPtr grids = volume::readVdbFile(vdb);
    const openvdb::GridBase& grid = *grids->front();
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    const glm::mat4 m = camera.projection(1.0f) * camera.view();
    std::array<double, 4> b = {1e30, 1e30, -1e30, -1e30};
    for (int i = 0; i < 8; ++i) {
        const openvdb::Vec3d index((i & 1 ? box.max() : box.min()).x() + (i & 1 ? 0.5 : -0.5),
                                   (i & 2 ? box.max() : box.min()).y() + (i & 2 ? 0.5 : -0.5),
                                   (i & 4 ? box.max() : box.min()).z() + (i & 4 ? 0.5 : -0.5));
        const openvdb::Vec3d w = grid.transform().indexToWorld(index);
        const glm::vec4 c = m * glm::vec4(float(w.x()), float(w.y()), float(w.z()), 1.0f);
        EXPECT_GT(c.w, 0.0f) << "a corner behind the camera";
        b[0] = std::min(b[0], double(c.x / c.w)), b[1] = std::min(b[1], double(c.y / c.w));
        b[2] = std::max(b[2], double(c.x / c.w)), b[3] = std::max(b[3], double(c.y / c.w));
    }
    return b;
}

} // namespace

TEST(VdbFramingTest, TheGridsBoxFillsTheFrame) {
    for (const char* file :
         {"vdb-sphere-fog/sphere.vdb", "vdb-smoke/smoke.vdb", "vdb-torus-fog/torus01.vdb",
          "vdb-wdas-cloud/wdas_cloud_sixteenth.vdb"}) {
        const std::filesystem::path vdb = dataDir() / file;
        const vdb::VdbScene s = vdb::sceneForVdb(vdb, "", {});
        const auto b = projectedBounds(vdb, s.scene.cameras.front());
        for (double v : b)
            EXPECT_LE(std::abs(v), 1.0) << file << ": a corner outside the image";
        // NDC spans 2 across the image.
        const double span = std::max(b[2] - b[0], b[3] - b[1]) / 2.0;
        std::printf("%s: the box spans %.0f%% of the image side\n", file, 100.0 * span);
        EXPECT_GE(span, 0.85) << file;
        // Centred: the margins left and right (or below and above) within 2% of the image.
        EXPECT_NEAR(b[0] + b[2], 0.0, 0.04) << file;
        EXPECT_NEAR(b[1] + b[3], 0.0, 0.04) << file;
    }
}

// frameBox itself against a hand-computed case: a cube of side 2 seen face on along +z,
// 90 degree field: its near face (z = 1) touches the border when 1 / (d - 1) = tan 45 deg x
// fill, d = 2 at fill 1 and 3 at fill 0.5; a centred projection keeps the target.
TEST(VdbFramingTest, FrameBoxOfACubeFaceOn) {
    const vdb::BoxFraming one = vdb::frameBox({-1, -1, -1}, {1, 1, 1}, {0, 0, 1}, 90.0, 1.0);
    EXPECT_NEAR(one.distance, 2.0, 1e-9);
    EXPECT_NEAR(glm::length(one.target), 0.0, 1e-9);
    EXPECT_NEAR(one.nearest, 1.0, 1e-9);
    EXPECT_NEAR(one.farthest, 3.0, 1e-9);
    EXPECT_NEAR(vdb::frameBox({-1, -1, -1}, {1, 1, 1}, {0, 0, 1}, 90.0, 0.5).distance, 3.0, 1e-9);
}

} // namespace veil::test
