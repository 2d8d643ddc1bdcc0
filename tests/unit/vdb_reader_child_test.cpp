// The reader child of grid/vdb_file.h: one child serves every read of its thread (no fork per
// file); a crash of the child on one file is one error naming the file and the next read gets
// a fresh child; a failed read replaces the child too; a VdbReadScope reads a file once however
// many of its grids are taken; and a frame's emission channel is read with its density and
// static grids are converted once per range (sequence/prefetch.h).
#include "grid/vdb_file.h"
#include "sequence/prefetch.h"
#include "support/test_support.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <thread>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path fireFrame(int n) {
    return dataDir() / "vdb-embergen-fire-seq" / fmt::format("embergen_fire_a_{}.vdb", n);
}

// Runs `f` on a thread of its own: a thread's reader child starts with its first read there.
template <typename F>
void onFreshThread(F&& f) {
    std::thread t(std::forward<F>(f));
    t.join();
}

} // namespace

TEST(VdbReaderChildTest, OneChildServesEveryReadOfAThread) {
    volume::readVdbFile(fireFrame(1)); // OpenVDB initialised, this thread's child started
    const int before = volume::readerStartsForTesting();
    onFreshThread([] {
        for (int i = 0; i < 8; ++i)
            EXPECT_FALSE(volume::readVdbFile(fireFrame(1 + i % 4))->empty());
    });
    EXPECT_EQ(volume::readerStartsForTesting() - before, 1);
}

TEST(VdbReaderChildTest, CrashOfTheReaderNamesTheFileAndTheNextReadWorks) {
    const fs::path dir = outputSubdir("vdb_reader_child");
    const fs::path victim = dir / "crashes-the-reader.vdb";
    fs::copy_file(fireFrame(2), victim, fs::copy_options::overwrite_existing);
    volume::readVdbFile(fireFrame(1));
    const int before = volume::readerStartsForTesting();
    std::string msg;
    onFreshThread([&] {
        ASSERT_FALSE(volume::readVdbFile(fireFrame(1))->empty());
        volume::setReaderCrashForTesting(victim.filename().string());
        msg = errorOf([&] { volume::readVdbFile(victim); });
        volume::setReaderCrashForTesting("");
        // The same file again, now read: a fresh child.
        EXPECT_FALSE(volume::readVdbFile(victim)->empty());
        EXPECT_FALSE(volume::readVdbFile(fireFrame(3))->empty());
    });
    EXPECT_NE(msg.find(victim.string()), std::string::npos) << msg;
    // SIGSEGV (11); under AddressSanitizer its handler turns the fault into an abort (6).
    EXPECT_NE(msg.find("the OpenVDB reader crashed on it (signal "), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_EQ(volume::readerStartsForTesting() - before, 2); // the first, and one after the crash
}

TEST(VdbReaderChildTest, FailedReadReplacesTheChild) {
    // Damage inside grid data that only the child's read finds (the header check passes).
    const fs::path cut = outputSubdir("vdb_reader_child") / "grid-data-shifts-next-descriptor.vdb";
    fs::copy_file(sourceDir() /
                      "tests/fuzz/regressions/volume/grid-data-shifts-next-descriptor.vdb",
                  cut, fs::copy_options::overwrite_existing);
    volume::readVdbFile(fireFrame(1));
    const int before = volume::readerStartsForTesting();
    std::string msg;
    onFreshThread([&] {
        ASSERT_FALSE(volume::readVdbFile(fireFrame(1))->empty());
        msg = errorOf([&] { volume::readVdbFile(cut); });
        EXPECT_FALSE(volume::readVdbFile(fireFrame(2))->empty());
    });
    EXPECT_NE(msg.find(cut.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("ends at byte"), std::string::npos) << msg; // found by the child
    EXPECT_EQ(volume::readerStartsForTesting() - before, 2);
}

TEST(VdbReaderChildTest, ReadScopeReadsAFileOnce) {
    int reads = 0;
    volume::setAfterTrialReadHookForTesting([&] { ++reads; });
    {
        const volume::VdbReadScope scope;
        const auto a = volume::readVdbFile(fireFrame(1));
        const auto b = volume::readVdbFile(fireFrame(1));
        EXPECT_EQ(a, b);
        volume::readVdbFile(fireFrame(2));
    }
    EXPECT_EQ(reads, 2);
    volume::readVdbFile(fireFrame(1)); // the scope is gone: read again
    volume::setAfterTrialReadHookForTesting({});
    EXPECT_EQ(reads, 3);
}

namespace {

// torus01.vdb as a static volume (first: converted ahead with the whole budget) and the fire
// frames 1-4 with their temperature as emission.
scene::AnimatedScene emissiveWithStatic() {
    const nlohmann::json doc = {
        {"cameras", {{{"position", {0, -62, -98}}, {"target", {0, 0, -112}}}}},
        {"volumes",
         {{{"name", "torus"},
           {"path", (dataDir() / "vdb-torus-fog" / "torus01.vdb").string()},
           {"grid", "voxel_fog_density"}},
          {{"name", "fire"},
           {"path", (dataDir() / "vdb-embergen-fire-seq" / "embergen_fire_a_#.vdb").string()},
           {"grid", "flames"},
           {"temperature_grid", "temperature"}}}}};
    const fs::path file =
        writeTextFile(outputSubdir("vdb_reader_child") / "emissive-static.json", doc.dump());
    return scene::loadAnimatedScene(file, {});
}

} // namespace

TEST(VdbReaderChildTest, FrameTakesItsEmissionChannelFromOneReadAndStaticGridsConvertOnce) {
    const scene::AnimatedScene scene = emissiveWithStatic();
    const auto statics = sequence::readStaticGrids(scene);
    ASSERT_EQ(statics.size(), 1u);
    sequence::StaticConversions conversions;
    int reads = 0;
    volume::setAfterTrialReadHookForTesting([&] { ++reads; });
    std::vector<sequence::PreparedFrame> frames;
    for (int f = 1; f <= 3; ++f)
        frames.push_back(sequence::prepareFrame(scene, f, statics, 2048, &conversions));
    volume::setAfterTrialReadHookForTesting({});
    EXPECT_EQ(reads, 3); // one read of each frame's file for flames and temperature
    for (const sequence::PreparedFrame& p : frames) {
        ASSERT_TRUE(p.error.empty()) << p.error;
        ASSERT_TRUE(volume::findPreloadedGridIn(p.grids, p.scene.volumes[1].path, "temperature"))
            << "frame " << p.frame;
        EXPECT_TRUE(volume::findPreloadedGridIn(p.grids, p.scene.volumes[1].path, "flames"));
        const auto torus = std::find_if(p.grids.begin(), p.grids.end(), [](const auto& g) {
            return g.grid == "voxel_fog_density";
        });
        ASSERT_NE(torus, p.grids.end());
        ASSERT_TRUE(torus->converted);
        EXPECT_EQ(torus->converted,
                  frames[0].grids[std::size_t(torus - p.grids.begin())].converted);
    }
    EXPECT_EQ(conversions.conversions(), 1u);
}

} // namespace veil::test
