// OpenVDB files read on several threads at once while other threads run TBB work, as the
// prefetch workers (one reading, one converting a grid with TBB) and the viewer's frame cache do.
// Each read forks a child for the trial read (grid/vdb_file.h). A child forked while another
// thread held one of OpenVDB's registry locks (taken for every grid and metadata item a decode
// creates) waited on it for ever; so did a child that used TBB (io::Stream's writer) while the
// parent's TBB workers were busy (grid/vdb_reply.h).
#include "support/test_support.h"
#include "grid/vdb_file.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define VEIL_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VEIL_UNDER_ASAN 1
#endif
#endif
#ifndef VEIL_UNDER_ASAN
#define VEIL_UNDER_ASAN 0
#endif

namespace veil::test {

TEST(VdbConcurrentReadTest, ReadersOnSeveralThreadsAllFinish) {
#if VEIL_UNDER_ASAN
    // The AddressSanitizer runtime of clang 14 does not take its allocator's locks around
    // fork(): a child forked while another thread allocates can spin or wait on them for ever,
    // whatever the code under test does (seen: children in __sanitizer::internal_sched_yield and
    // SizeClassAllocator64::GetFromAllocator). The release build runs this test.
    GTEST_SKIP() << "fork beside allocating threads can hang under this ASan runtime";
#endif
    std::vector<std::filesystem::path> files;
    for (int i = 1; i <= 4; ++i)
        files.push_back(dataDir() /
                        ("vdb-embergen-fire-seq/embergen_fire_a_" + std::to_string(i) + ".vdb"));
    constexpr int kThreads = 4, kReads = 30;
    std::atomic<int> done{0}, failed{0};
    std::atomic<bool> stop{false};
    // TBB kept busy on 8 threads (more than this machine's cores, as on a GPU machine's 16).
    std::thread busy([&] {
        tbb::task_arena arena(8);
        arena.execute([&] {
            std::vector<float> v(1 << 16);
            while (!stop)
                tbb::parallel_for(std::size_t(0), v.size(),
                                  [&](std::size_t i) { v[i] = v[i] * 0.5f + float(i); });
        });
    });
    std::vector<std::thread> readers;
    for (int t = 0; t < kThreads; ++t)
        readers.emplace_back([&, t] {
            for (int i = 0; i < kReads; ++i) {
                try {
                    if (volume::readVdbFile(files[std::size_t(t + i) % files.size()])->empty())
                        ++failed;
                } catch (const std::exception&) {
                    ++failed;
                }
                ++done;
            }
        });
    // A hung child holds its reader for the trial read's timeout (minutes): give up long before,
    // without joining the readers that will not come back.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(90);
    while (done < kThreads * kReads && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (done < kThreads * kReads) {
        std::fprintf(stderr,
                     "VdbConcurrentReadTest: %d of %d reads finished in 90 s: a trial "
                     "read's child is stuck\n",
                     done.load(), kThreads * kReads);
        std::fflush(stderr);
        std::_Exit(1);
    }
    stop = true;
    busy.join();
    for (std::thread& r : readers)
        r.join();
    EXPECT_EQ(failed, 0);
}

} // namespace veil::test
