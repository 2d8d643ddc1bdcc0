// `veil export` and `veil voxelize` with --frame / --frames: each frame of a file sequence goes
// to the output with its frame number, equal to the same command run on that frame's file
// alone; a missing frame is one line naming the file before anything is written; outputs of a
// range need a frame pattern.
#include "io/vtk_export.h"
#include "support/test_support.h"
#include "support/vdb_read.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fstream>
#include <map>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir(const std::string& name) { return freshOutputDir("frames_export", name); }

fs::path fire(const std::string& name) { return dataDir() / "vdb-embergen-fire-seq" / name; }

CommandResult veil(const std::string& args) { return runCommand(veilExe() + " " + args); }

std::map<std::string, std::string> fields(const io::DenseGrid& g) {
    return {g.fieldData.begin(), g.fieldData.end()};
}

// An axis-aligned box [lo, lo + size]^3 as an OBJ (12 triangles, outward winding).
void writeBox(const fs::path& path, float lo, float size) {
    std::ofstream o(path);
    for (int c = 0; c < 8; ++c)
        o << "v " << lo + size * (c & 1) << ' ' << lo + size * ((c >> 1) & 1) << ' '
          << lo + size * ((c >> 2) & 1) << '\n';
    o << "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\n"
         "f 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n";
}

} // namespace

TEST(FramesExportTest, ExportRangeEqualsExportOfEachFile) {
    const fs::path d = dir("export");
    const std::string pattern = shellQuote(fire("embergen_fire_a_#.vdb"));
    const CommandResult r = veil("export " + pattern + " --grid flames --frames 2-3 -o " +
                                 shellQuote(d / "f.####.vti"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::vector<io::DenseGrid> frames;
    for (int f = 2; f <= 3; ++f) {
        const fs::path file = fire(fmt::format("embergen_fire_a_{}.vdb", f));
        const fs::path single = d / fmt::format("single{}.vti", f);
        const CommandResult s =
            veil("export " + shellQuote(file) + " --grid flames -o " + shellQuote(single));
        ASSERT_EQ(s.exitCode, 0) << s.output;
        frames.push_back(io::readVti(d / fmt::format("f.{:04d}.vti", f)));
        const io::DenseGrid alone = io::readVti(single);
        EXPECT_EQ(frames.back().dims, alone.dims);
        EXPECT_EQ(frames.back().origin, alone.origin);
        EXPECT_EQ(frames.back().values, alone.values) << "frame " << f;
        EXPECT_EQ(fields(frames.back()).at("veil_source"), file.string());
    }
    EXPECT_NE(frames[0].values, frames[1].values); // the fire changes frame to frame
    EXPECT_FALSE(fs::exists(d / "f.0001.vti"));
    EXPECT_FALSE(fs::exists(d / "f.0004.vti"));
}

TEST(FramesExportTest, MissingFrameAndBadOptionsAreOneClearLine) {
    const fs::path d = dir("errors");
    const std::string pattern = shellQuote(fire("embergen_fire_a_#.vdb"));
    // Frame 5 does not exist: named, and frames 3-4 are not written either.
    CommandResult r = veil("export " + pattern + " --grid flames --frames 3-5 -o " +
                           shellQuote(d / "f.####.vti"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("embergen_fire_a_5.vdb: frame 5 of"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::is_empty(d));
    // A range into one file name; --frame on a plain file; a sequence without a frame.
    r = veil("export " + pattern + " --frames 1-2 -o " + shellQuote(d / "one.vti"));
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("no frame pattern"), std::string::npos) << r.output;
    r = veil("export " + shellQuote(fire("embergen_fire_a_1.vdb")) + " --frame 1 -o " +
             shellQuote(d / "one.vti"));
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("need a file sequence"), std::string::npos) << r.output;
    r = veil("export " + pattern + " -o " + shellQuote(d / "one.vti"));
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("is a file sequence: give --frame"), std::string::npos) << r.output;
    r = veil("export " + pattern + " --frames 3-1 -o " + shellQuote(d / "f.####.vti"));
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_TRUE(fs::is_empty(d));
}

TEST(FramesExportTest, VoxelizeMeshSequenceEqualsEachFileAlone) {
    const fs::path d = dir("voxelize");
    writeBox(d / "box.1.obj", 0.0f, 1.0f);
    writeBox(d / "box.2.obj", 0.25f, 0.5f);
    const CommandResult r =
        veil("voxelize " + shellQuote(d / "box.#.obj") +
             " --frames 1-2 --res 12 --solid --quiet -o " + shellQuote(d / "v.###.vdb"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (int f = 1; f <= 2; ++f) {
        const fs::path alone = d / fmt::format("alone{}.vdb", f);
        const CommandResult s = veil("voxelize " + shellQuote(d / fmt::format("box.{}.obj", f)) +
                                     " --res 12 --solid --quiet -o " + shellQuote(alone));
        ASSERT_EQ(s.exitCode, 0) << s.output;
        const auto a = readVdbGrids(d / fmt::format("v.{:03d}.vdb", f));
        const auto b = readVdbGrids(alone);
        ASSERT_EQ(a->size(), b->size());
        for (std::size_t i = 0; i < a->size(); ++i) {
            EXPECT_EQ((*a)[i]->getName(), (*b)[i]->getName());
            EXPECT_GT((*a)[i]->activeVoxelCount(), 0u);
            EXPECT_EQ((*a)[i]->activeVoxelCount(), (*b)[i]->activeVoxelCount()) << "frame " << f;
            EXPECT_EQ((*a)[i]->transform(), (*b)[i]->transform());
            const auto ga = openvdb::gridPtrCast<openvdb::FloatGrid>((*a)[i]);
            const auto gb = openvdb::gridPtrCast<openvdb::FloatGrid>((*b)[i]);
            if (!ga || !gb) continue; // the mask: its active voxels are compared above
            auto acc = gb->getConstAccessor();
            std::size_t differ = 0;
            for (auto v = ga->cbeginValueOn(); v; ++v)
                differ += acc.getValue(v.getCoord()) != *v;
            EXPECT_EQ(differ, 0u) << "frame " << f;
        }
    }
    // The two frames differ (the second box is half the size: so are its voxels).
    EXPECT_NE(readVdbGrids(d / "v.001.vdb")->front()->transform(),
              readVdbGrids(d / "v.002.vdb")->front()->transform());
    // A missing frame is named before any GL work or output.
    const CommandResult m = veil("voxelize " + shellQuote(d / "box.#.obj") +
                                 " --frames 2-3 --res 12 -o " + shellQuote(d / "m.####.vdb"));
    EXPECT_EQ(m.exitCode, 1) << m.output;
    EXPECT_NE(m.output.find("box.3.obj: frame 3 of"), std::string::npos) << m.output;
    EXPECT_FALSE(fs::exists(d / "m.0002.vdb"));
}

} // namespace veil::test
