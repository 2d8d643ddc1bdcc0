// The reader child of grid/vdb_file.h: one child serves every read of its thread (no fork per
// file); a crash of the child on one file is one error naming the file and the next read gets
// a fresh child; a failed read replaces the child too; a VdbReadScope reads a file once however
// many of its grids are taken; and a frame's emission channel is read with its density and
// static grids are converted once per range (sequence/prefetch.h). The child's reply comes
// through sealed shared memory (grid/vdb_reply.h): the grids it gives equal OpenVDB's own read
// of the file voxel for voxel, and a reply cut short, left unsealed or not in shared memory at
// all is refused with one message naming the file. A frame's grids are freed on the releaser's
// thread, not the render thread.
#include "grid/vdb_file.h"
#include "grid/vdb_reply.h"
#include "sequence/prefetch.h"
#include "support/test_support.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <fstream>
#include <mutex>
#include <thread>

#include <fcntl.h>
#include <unistd.h>

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

namespace {

// `a` and `b` hold the same grids (in any order): names, types, transforms, background, topology
// and, for float grids, every leaf's values (active and inactive) and every active tile's value.
void expectSameGrids(const openvdb::GridPtrVec& a, openvdb::GridPtrVec b) {
    ASSERT_EQ(a.size(), b.size());
    // In the order of `a` (io::File::getGrids() gives them in another).
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = i; j < b.size(); ++j)
            if (b[j]->getName() == a[i]->getName()) std::swap(b[i], b[j]);
    for (std::size_t i = 0; i < a.size(); ++i) {
        SCOPED_TRACE(a[i]->getName());
        EXPECT_EQ(a[i]->getName(), b[i]->getName());
        ASSERT_EQ(a[i]->type(), b[i]->type());
        EXPECT_EQ(a[i]->transform(), b[i]->transform());
        EXPECT_EQ(a[i]->activeVoxelCount(), b[i]->activeVoxelCount());
        const auto fa = openvdb::gridPtrCast<openvdb::FloatGrid>(a[i]);
        const auto fb = openvdb::gridPtrCast<openvdb::FloatGrid>(b[i]);
        if (!fa) continue;
        EXPECT_EQ(fa->background(), fb->background());
        ASSERT_TRUE(fa->tree().hasSameTopology(fb->tree()));
        std::size_t leaves = 0, differing = 0;
        auto lb = fb->tree().cbeginLeaf();
        for (auto la = fa->tree().cbeginLeaf(); la; ++la, ++lb, ++leaves)
            differing += la->origin() != lb->origin() ||
                         std::memcmp(la->buffer().data(), lb->buffer().data(),
                                     sizeof(float) * la->size()) != 0;
        EXPECT_EQ(differing, 0u) << "of " << leaves << " leaves";
        EXPECT_GT(leaves, 0u);
        for (auto v = fa->tree().cbeginValueOn(); v; ++v)
            if (v.isTileValue()) {
                EXPECT_EQ(*v, fb->tree().getValue(v.getCoord()));
            }
    }
}

} // namespace

TEST(VdbReaderChildTest, SharedMemoryReplyEqualsTheFileVoxelForVoxel) {
    for (int n : {1, 4}) {
        const openvdb::GridPtrVecPtr got = volume::readVdbFile(fireFrame(n));
        openvdb::io::File file(fireFrame(n).string()); // test data: OpenVDB's own read here
        file.open();
        const openvdb::GridPtrVecPtr want = file.getGrids();
        file.close();
        expectSameGrids(*got, *want);
    }
}

TEST(VdbReaderChildTest, DamagedReplyIsRefusedNamingTheFile) {
    const fs::path dir = outputSubdir("vdb_reader_child");
    for (const auto& [kind, reason] :
         {std::pair{1, "ends inside grid"}, std::pair{2, "is not sealed shared memory"}}) {
        SCOPED_TRACE(reason);
        const fs::path victim = dir / fmt::format("damaged-reply-{}.vdb", kind);
        fs::copy_file(fireFrame(3), victim, fs::copy_options::overwrite_existing);
        std::string msg;
        onFreshThread([&] {
            volume::setReplyDamageForTesting(victim.filename().string(), kind);
            msg = errorOf([&] { volume::readVdbFile(victim); });
            volume::setReplyDamageForTesting("", 0);
            EXPECT_FALSE(volume::readVdbFile(victim)->empty()); // undamaged now
        });
        EXPECT_NE(msg.find(victim.string()), std::string::npos) << msg;
        EXPECT_NE(msg.find("re-encoding could not be decoded"), std::string::npos) << msg;
        EXPECT_NE(msg.find(reason), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

TEST(VdbReaderChildTest, ReplyOutsideSealedSharedMemoryIsRefused) {
    const openvdb::GridPtrVecPtr grids = volume::readVdbFile(fireFrame(2));
    // The same bytes in a file on disk: no seals to check, refused.
    const fs::path onDisk = outputSubdir("vdb_reader_child") / "reply-on-disk.bin";
    {
        std::ofstream out(onDisk, std::ios::binary);
        volume::writeGridReply(out, *grids);
    }
    const int fd = ::open(onDisk.c_str(), O_RDONLY | O_CLOEXEC);
    ASSERT_GE(fd, 0);
    const std::string disk =
        errorOf([&] { volume::readGridReplyFromMemory(fd, fs::file_size(onDisk)); });
    ::close(fd);
    EXPECT_NE(disk.find("not sealed shared memory"), std::string::npos) << disk;
    // Sealed shared memory, but not of the size announced; then as announced, decoded.
    std::uint64_t size = 0;
    const int memory = volume::writeGridReplyToMemory(*grids, 0, size);
    const std::string longer = errorOf([&] { volume::readGridReplyFromMemory(memory, size + 1); });
    EXPECT_NE(longer.find(fmt::format("not of the {} bytes announced", size + 1)),
              std::string::npos)
        << longer;
    const openvdb::GridPtrVecPtr again = volume::readGridReplyFromMemory(memory, size);
    ::close(memory);
    expectSameGrids(*again, *grids);
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

// The render thread hands a frame's grids and conversions to the releaser (sequence/prefetch.h)
// once uploaded: they are freed on its thread, not the caller's, and all of them by the time
// the releaser is gone.
TEST(VdbReaderChildTest, GridReleaserFreesOnItsOwnThread) {
    std::mutex mutex;
    std::vector<std::thread::id> freedOn;
    const auto caller = std::this_thread::get_id();
    {
        sequence::GridReleaser releaser;
        for (int frame = 0; frame < 3; ++frame) {
            std::vector<volume::PreloadedGrid> grids(2);
            for (volume::PreloadedGrid& g : grids)
                g.value = openvdb::FloatGrid::Ptr(new openvdb::FloatGrid, [&](auto* p) {
                    const std::lock_guard lock(mutex);
                    freedOn.push_back(std::this_thread::get_id());
                    delete p;
                });
            releaser.release(std::move(grids));
            EXPECT_TRUE(grids.empty());
        }
    }
    ASSERT_EQ(freedOn.size(), 6u);
    for (const std::thread::id& id : freedOn)
        EXPECT_NE(id, caller);
}

} // namespace veil::test
