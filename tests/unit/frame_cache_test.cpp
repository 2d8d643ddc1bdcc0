// The viewer's frame stream (session/frame_cache.h) on the EmberGen fire files, without GL:
// frames come prepared (scene at the frame, grid read and converted) in the order asked,
// lookups never wait, the cache stays within its budget (plus the one frame it always
// loads) dropping frames no longer wanted first, and a missing file is a frame with an error.
#include "viewer/session/frame_cache.h"
#include "support/test_support.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <thread>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

std::shared_ptr<const scene::AnimatedScene> fireScene(const fs::path& pattern) {
    const nlohmann::json doc = {
        {"cameras", {{{"position", {0, -62, -98}}, {"target", {0, 0, -112}}}}},
        {"volumes", {{{"name", "fire"}, {"path", pattern.string()}, {"grid", "flames"}}}}};
    const fs::path file = writeTextFile(outputSubdir("frame_cache") /
                                            (pattern.parent_path().filename().string() + ".json"),
                                        doc.dump());
    return std::make_shared<const scene::AnimatedScene>(scene::loadAnimatedScene(file, {}));
}

// Polls find() for up to 60 s.
std::shared_ptr<const sequence::PreparedFrame> await(session::FrameCache& c, int frame) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < end) {
        if (auto p = c.find(frame)) return p;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return nullptr;
}

} // namespace

TEST(FrameCacheTest, PreparesWantedFramesWithinTheBudget) {
    const auto scene = fireScene(dataDir() / "vdb-embergen-fire-seq" / "embergen_fire_a_#.vdb");
    std::size_t frameBytes = 0;
    {
        session::FrameCache all(scene, std::size_t(1) << 30, 2048);
        EXPECT_EQ(all.find(3), nullptr); // not asked for: no wait, nothing
        all.want({3});
        const auto p = await(all, 3);
        ASSERT_TRUE(p);
        ASSERT_TRUE(p->error.empty()) << p->error;
        EXPECT_EQ(p->frame, 3);
        ASSERT_EQ(p->grids.size(), 1u);
        EXPECT_NE(p->grids[0].path.string().find("embergen_fire_a_3.vdb"), std::string::npos);
        ASSERT_TRUE(p->grids[0].converted); // converted for the GPU on the cache's thread
        EXPECT_EQ(p->grids[0].converted->stats.activeVoxels, p->activeVoxels);
        frameBytes = p->bytes;
    }
    ASSERT_GT(frameBytes, 0u);
    // Room for about one and a half frames: the urgent frame and one look-ahead at most.
    const std::size_t budget = frameBytes * 3 / 2;
    session::FrameCache c(scene, budget, 2048);
    c.want({1, 2, 3, 4});
    ASSERT_TRUE(await(c, 1));
    ASSERT_TRUE(await(c, 2)) << "look-ahead while under the budget: " << c.bytes() << " of "
                             << budget << " bytes, " << c.frames() << " frames, " << c.loads()
                             << " loads";
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_EQ(c.find(4), nullptr) << "loaded past the budget";
    EXPECT_LE(c.frames(), 2u);
    // Scrubbing to 4: frames no longer wanted make room; 4 comes whatever the budget.
    c.want({4});
    ASSERT_TRUE(await(c, 4));
    EXPECT_LE(c.bytes(), budget + frameBytes * 2);
    EXPECT_LE(c.frames(), 2u);
    EXPECT_GE(c.loads(), 3u);
}

TEST(FrameCacheTest, MissingFrameComesBackWithItsError) {
    const fs::path d = freshOutputDir("frame_cache", "missing");
    for (int f : {1, 3, 4}) // frame 2 missing (with 1 and 3 only, the step would be 2)
        fs::copy_file(dataDir() / "vdb-embergen-fire-seq" /
                          fmt::format("embergen_fire_a_{}.vdb", f),
                      d / fmt::format("f_{}.vdb", f));
    session::FrameCache c(fireScene(d / "f_#.vdb"), std::size_t(1) << 30, 0);
    c.want({2, 3});
    const auto p = await(c, 2);
    ASSERT_TRUE(p);
    EXPECT_NE(p->error.find("f_2.vdb"), std::string::npos) << p->error;
    EXPECT_TRUE(p->grids.empty());
    const auto q = await(c, 3);
    ASSERT_TRUE(q);
    EXPECT_TRUE(q->error.empty()) << q->error;
    EXPECT_FALSE(q->grids.at(0).converted); // max3D 0: read only
}

} // namespace veil::test
