// Writes tests/fuzz/corpus/volume/veil-small.vdb, the volume fuzzer's own small seed: one
// file with the kinds of grid loadDensityGrid tells apart (docs/fuzzing.md "Corpora"):
//   density  float fog, an 8^3 block with a ramp
//   half     float fog saved as half floats, with a NaN and negative values
//   ls       float level set sphere (radius 3 voxels at (6, 6, 6)), converted to fog on load
//   vel      Vec3s grid, refused on load
//   empty    float grid without active voxels, refused on load
// Zip and active-mask compression; the 45 KB are mostly each grid's internal-node masks.
// Build and run: cmake --build --preset fuzz --target veil_fuzz_make_seed_vdb &&
//   build/fuzz/tests/fuzz/veil_fuzz_make_seed_vdb tests/fuzz/corpus/volume/veil-small.vdb
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <cmath>
#include <cstdio>
#include <limits>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT.vdb\n", argv[0]);
        return 2;
    }
    openvdb::initialize();
    openvdb::GridPtrVec grids;

    auto density = openvdb::FloatGrid::create(0.0f);
    density->setName("density");
    density->setGridClass(openvdb::GRID_FOG_VOLUME);
    density->setTransform(openvdb::math::Transform::createLinearTransform(0.1));
    auto acc = density->getAccessor();
    for (int x = 0; x < 8; ++x)
        for (int y = 0; y < 8; ++y)
            for (int z = 0; z < 8; ++z)
                acc.setValue(openvdb::Coord(x, y, z), float(x + y + z) / 21.0f);
    density->setSaveFloatAsHalf(false);
    grids.push_back(density);

    auto half = openvdb::FloatGrid::create(0.0f);
    half->setName("half");
    half->setGridClass(openvdb::GRID_FOG_VOLUME);
    auto hacc = half->getAccessor();
    for (int i = 0; i < 8; ++i)
        hacc.setValue(openvdb::Coord(i, 2 * i, i), 0.25f * float(i) - 0.5f);
    hacc.setValue(openvdb::Coord(9, 9, 9), std::numeric_limits<float>::quiet_NaN());
    half->setSaveFloatAsHalf(true);
    grids.push_back(half);

    auto ls = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(3.0f, openvdb::Vec3f(6.0f),
                                                                       1.0f, 2.0f);
    ls->setName("ls");
    grids.push_back(ls);

    auto vel = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    vel->setName("vel");
    vel->getAccessor().setValue(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1.0f, 0.0f, -1.0f));
    grids.push_back(vel);

    auto empty = openvdb::FloatGrid::create(0.0f);
    empty->setName("empty");
    grids.push_back(empty);

    openvdb::io::File file(argv[1]);
    file.setCompression(openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
    file.write(grids);
    file.close();
    return 0;
}
