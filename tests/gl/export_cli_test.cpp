// `veil export grid.vdb -o grid.vti` , read back with VTK's own
// vtkXMLImageDataReader and checked against OpenVDB's values and sampling at the same points.
#include "io/vtk_export.h"
#include "support/test_support.h"
#include "support/vdb_read.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLImageDataReader.h>

#include <map>
#include <random>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() { return outputSubdir("export_cli"); }

vtkSmartPointer<vtkImageData> readVti(const fs::path& path) {
    vtkNew<vtkXMLImageDataReader> reader;
    reader->SetFileName(path.string().c_str());
    reader->Update();
    vtkSmartPointer<vtkImageData> image = reader->GetOutput();
    return image;
}

double valueAt(vtkImageData* image, int x, int y, int z, int component = 0) {
    int dims[3];
    image->GetDimensions(dims);
    const vtkIdType id = (vtkIdType(z) * dims[1] + y) * dims[0] + x;
    return image->GetPointData()->GetArray(0)->GetComponent(id, component);
}

} // namespace

TEST(ExportCliTest, SmokeGridMatchesOpenVdb) {
    const fs::path vdb = dataDir() / "vdb-smoke" / "smoke.vdb", out = dir() / "smoke.vti";
    fs::remove(out);
    const CommandResult r =
        runCommand(veilExe() + " export " + shellQuote(vdb) + " -o " + shellQuote(out));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("grid 0 'density' (float)"), std::string::npos) << r.output;
    // Provenance as field data: the source file, the grid, the version and the command.
    const io::DenseGrid dense = io::readVti(out);
    const std::map<std::string, std::string> field(dense.fieldData.begin(), dense.fieldData.end());
    EXPECT_EQ(field.at("veil_source"), vdb.string());
    EXPECT_EQ(field.at("veil_grid"), "0 'density' (float)");
    EXPECT_NE(field.at("veil_version").find("(commit "), std::string::npos);
    EXPECT_NE(field.at("veil_command").find(" export " + vdb.string() + " -o "), std::string::npos)
        << field.at("veil_command");

    const openvdb::GridPtrVecPtr grids = readVdbGrids(vdb);
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(grids->at(0));
    ASSERT_TRUE(grid);
    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    const vtkSmartPointer<vtkImageData> image = readVti(out);
    ASSERT_TRUE(image);
    int dims[3];
    double spacing[3], origin[3];
    image->GetDimensions(dims);
    image->GetSpacing(spacing);
    image->GetOrigin(origin);
    const openvdb::Vec3d world0 = grid->indexToWorld(box.min());
    for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(dims[a], box.dim()[a]) << a;
        EXPECT_NEAR(spacing[a], grid->voxelSize()[a], 1e-12) << a;
        EXPECT_NEAR(origin[a], world0[a], 1e-9) << a;
    }
    ASSERT_EQ(image->GetPointData()->GetArray(0)->GetNumberOfComponents(), 1);
    EXPECT_STREQ(image->GetPointData()->GetArray(0)->GetName(), "density");
    // Every exported point equals the voxel at the same world position; sample a few hundred
    // and the densest voxel.
    const auto acc = grid->getConstAccessor();
    std::mt19937 rng(12);
    int nonzero = 0;
    for (int i = 0; i < 400; ++i) {
        const int x = int(rng() % dims[0]), y = int(rng() % dims[1]), z = int(rng() % dims[2]);
        const openvdb::Vec3d w(origin[0] + x * spacing[0], origin[1] + y * spacing[1],
                               origin[2] + z * spacing[2]);
        const openvdb::Coord c = grid->transform().worldToIndexNodeCentered(w);
        EXPECT_EQ(valueAt(image, x, y, z), acc.getValue(c)) << x << "," << y << "," << z;
        nonzero += acc.getValue(c) != 0.0f;
    }
    EXPECT_GT(nonzero, 20);
    float maxValue = 0.0f;
    openvdb::Coord maxCoord;
    for (auto it = grid->cbeginValueOn(); it; ++it)
        if (*it > maxValue) maxValue = *it, maxCoord = it.getCoord();
    const openvdb::Coord m = maxCoord - box.min();
    EXPECT_EQ(valueAt(image, m.x(), m.y(), m.z()), maxValue);
}

TEST(ExportCliTest, BoxAndResampleFollowOpenVdbSampling) {
    const fs::path vdb = dataDir() / "vdb-smoke" / "smoke.vdb", out = dir() / "box.vti";
    const CommandResult r =
        runCommand(veilExe() + " export " + shellQuote(vdb) + " -o " + shellQuote(out) +
                   " --grid 0 --box 40 60 40 60 90 70 --resample 2");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(readVdbGrids(vdb)->at(0));
    const vtkSmartPointer<vtkImageData> image = readVti(out);
    int dims[3];
    double spacing[3], origin[3];
    image->GetDimensions(dims);
    image->GetSpacing(spacing);
    image->GetOrigin(origin);
    EXPECT_EQ(dims[0], 41);
    EXPECT_EQ(dims[1], 61);
    EXPECT_EQ(dims[2], 61);
    EXPECT_NEAR(spacing[0], grid->voxelSize()[0] / 2.0, 1e-12);
    const openvdb::Vec3d w0 = grid->indexToWorld(openvdb::Coord(40, 60, 40));
    EXPECT_NEAR(origin[1], w0[1], 1e-9);
    // Trilinear sampling of OpenVDB at the same world points.
    const auto acc = grid->getConstAccessor();
    std::mt19937 rng(5);
    double maxDiff = 0.0, sum = 0.0;
    for (int i = 0; i < 300; ++i) {
        const int x = int(rng() % dims[0]), y = int(rng() % dims[1]), z = int(rng() % dims[2]);
        const openvdb::Vec3d w(origin[0] + x * spacing[0], origin[1] + y * spacing[1],
                               origin[2] + z * spacing[2]);
        const double expected =
            openvdb::tools::BoxSampler::sample(acc, grid->transform().worldToIndex(w));
        maxDiff = std::max(maxDiff, std::abs(valueAt(image, x, y, z) - expected));
        sum += expected;
    }
    EXPECT_LT(maxDiff, 1e-5);
    EXPECT_GT(sum, 1.0);
}

TEST(ExportCliTest, VectorGridsAndBadSelectionsNameFileAndGrid) {
    openvdb::initialize();
    auto mask = openvdb::BoolGrid::create(false);
    mask->setName("mask");
    mask->tree().setValueOn(openvdb::Coord(0, 0, 0), true);
    auto velocity = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    velocity->setName("v");
    velocity->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
    for (int i = 0; i < 4; ++i)
        velocity->tree().setValue(openvdb::Coord(i, 2 * i, 1), openvdb::Vec3s(i, -i, 0.5f * i));
    const fs::path vdb = dir() / "mixed.vdb";
    openvdb::io::File(vdb.string()).write({mask, velocity});

    const fs::path out = dir() / "v.vti";
    CommandResult r =
        runCommand(veilExe() + " export " + shellQuote(vdb) + " -o " + shellQuote(out));
    ASSERT_EQ(r.exitCode, 0) << r.output; // the first float or vec3 grid: index 1
    EXPECT_NE(r.output.find("grid 1 'v' (vec3s)"), std::string::npos) << r.output;
    const vtkSmartPointer<vtkImageData> image = readVti(out);
    int dims[3];
    image->GetDimensions(dims);
    EXPECT_EQ(dims[0], 4);
    EXPECT_EQ(dims[1], 7);
    EXPECT_EQ(dims[2], 1);
    ASSERT_EQ(image->GetPointData()->GetArray(0)->GetNumberOfComponents(), 3);
    EXPECT_EQ(valueAt(image, 3, 6, 0, 0), 3.0);
    EXPECT_EQ(valueAt(image, 3, 6, 0, 1), -3.0);
    EXPECT_EQ(valueAt(image, 3, 6, 0, 2), 1.5);
    EXPECT_EQ(valueAt(image, 1, 0, 0, 0), 0.0); // inactive: the background
    EXPECT_NEAR(image->GetSpacing()[0], 0.25, 1e-12);

    const fs::path bad = dir() / "bad.vti";
    fs::remove(bad);
    struct Case {
        std::string args, expect;
    };
    for (const Case& c : std::vector<Case>{
             {"--grid mask", "mixed.vdb': grid 0 'mask' is bool, not a float or vec3 grid"},
             {"--grid nope", "mixed.vdb' has no grid named 'nope' (grids: 0 'mask' (bool), 1 "
                             "'v' (vec3s))"},
             {"--grid 7", "mixed.vdb' has no grid 7"},
             {"--box 3 3 3 1 1 1", "--box"}}) {
        r = runCommand(veilExe() + " export " + shellQuote(vdb) + " -o " + shellQuote(bad) + " " +
                       c.args);
        EXPECT_EQ(r.exitCode, 1) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
        EXPECT_FALSE(fs::exists(bad));
    }
    r = runCommand(veilExe() + " export " + shellQuote(dir() / "missing.vdb") + " -o " +
                   shellQuote(bad));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("missing.vdb"), std::string::npos) << r.output;
}

} // namespace veil::test
