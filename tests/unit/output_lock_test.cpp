// Locks of frame outputs (base/output_lock.h) between processes: a second run over a frame
// another run holds is refused naming the frame, that run's pid and the lock file; disjoint
// frames of one pattern (the slices of a Slurm array) go on side by side; a killed holder
// releases its frames; a lock file that is a link is never used.
#include "base/error.h"
#include "base/output_lock.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

fs::path testDir(const std::string& name) {
    const fs::path dir = fs::path(VEIL_TEST_OUTPUT_DIR) / "output_lock_test" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string lockError(const fs::path& output, const std::vector<int>& frames) {
    try {
        veil::OutputLock lock(output, frames, "veil render");
    } catch (const veil::Error& e) {
        return e.what();
    }
    return "";
}

// A child process holding `frames` of `output` until it is killed.
class Holder {
public:
    Holder(const fs::path& output, const std::vector<int>& frames) {
        int ready[2];
        if (::pipe(ready) != 0) throw std::runtime_error("pipe");
        pid_ = ::fork();
        if (pid_ == 0) {
            ::close(ready[0]);
            char c = 'n';
            try {
                veil::OutputLock lock(output, frames, "veil render");
                c = 'y';
                (void)!::write(ready[1], &c, 1);
                for (;;)
                    ::pause();
            } catch (...) {
                (void)!::write(ready[1], &c, 1);
            }
            ::_exit(1);
        }
        ::close(ready[1]);
        char c = 0;
        held_ = ::read(ready[0], &c, 1) == 1 && c == 'y';
        ::close(ready[0]);
    }
    ~Holder() { kill(); }
    void kill() {
        if (pid_ <= 0) return;
        ::kill(pid_, SIGKILL);
        int status = 0;
        ::waitpid(pid_, &status, 0);
        pid_ = -1;
    }
    bool held() const { return held_; }
    pid_t pid() const { return pid_; }

private:
    pid_t pid_ = -1;
    bool held_ = false;
};

} // namespace

TEST(OutputLockTest, SecondRunOverAHeldFrameIsRefused) {
    const fs::path dir = testDir("held");
    const fs::path pattern = dir / "f.####.png";
    Holder first(pattern, {1, 2, 3, 4, 5});
    ASSERT_TRUE(first.held());
    const fs::path file = veil::OutputLock::fileFor(pattern);
    EXPECT_EQ(file, dir / ".f.####.png.lock");
    const std::string m = lockError(pattern, {5, 6, 7});
    EXPECT_NE(m.find("frame 5 of output '" + pattern.string() + "'"), std::string::npos) << m;
    EXPECT_NE(m.find("pid " + std::to_string(first.pid())), std::string::npos) << m;
    EXPECT_NE(m.find(file.string()), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    // Every frame of the range is checked, not only the first: 0 and 8 are free, 3 is not.
    EXPECT_NE(lockError(pattern, {0, 3, 8}).find("frame 3 of"), std::string::npos);
    // The whole output (a video) overlaps every frame.
    EXPECT_NE(lockError(pattern, {}).find("output '" + pattern.string() + "' is being written"),
              std::string::npos);
    // Disjoint frames of the same pattern, and other patterns, go on.
    EXPECT_EQ(lockError(pattern, {6, 7, 8}), "");
    EXPECT_EQ(lockError(pattern, {-3, 100000}), "");
    EXPECT_EQ(lockError(dir / "g.####.png", {1, 2, 3}), "");
    // A killed run holds nothing: its lock file is taken over.
    first.kill();
    EXPECT_TRUE(fs::exists(file));
    EXPECT_EQ(lockError(pattern, {1, 2, 3}), "");
    EXPECT_FALSE(fs::exists(file)) << "the last holder removes the lock file";
}

TEST(OutputLockTest, TwoRunsOverDisjointSlicesHoldTogether) {
    const fs::path dir = testDir("slices");
    const fs::path pattern = dir / "s.%04d.exr";
    Holder even(pattern, {0, 2, 4, 6});
    Holder odd(pattern, {1, 3, 5, 7});
    EXPECT_TRUE(even.held());
    EXPECT_TRUE(odd.held());
    const std::string m = lockError(pattern, {7, 8});
    EXPECT_NE(m.find("frame 7 of"), std::string::npos) << m;
    EXPECT_NE(m.find("pid " + std::to_string(odd.pid())), std::string::npos) << m;
}

TEST(OutputLockTest, LinkedLockFileIsRefusedAndLeftAlone) {
    const fs::path dir = testDir("links");
    const fs::path victim = dir / "victim.txt";
    std::ofstream(victim) << "keep";
    const fs::path pattern = dir / "f.####.png";
    fs::create_symlink(victim, veil::OutputLock::fileFor(pattern));
    std::string m = lockError(pattern, {1});
    EXPECT_NE(m.find("symbolic link"), std::string::npos) << m;
    fs::remove(veil::OutputLock::fileFor(pattern));
    fs::create_hard_link(victim, veil::OutputLock::fileFor(pattern));
    m = lockError(pattern, {1});
    EXPECT_NE(m.find("hard link"), std::string::npos) << m;
    std::string text;
    std::ifstream(victim) >> text;
    EXPECT_EQ(text, "keep");
    EXPECT_EQ(fs::file_size(victim), 4u);
}

TEST(OutputLockTest, LongNamesGetAShortLockFile) {
    const fs::path dir = testDir("long");
    const fs::path output = dir / (std::string(250, 'l') + ".png");
    const fs::path file = veil::OutputLock::fileFor(output);
    EXPECT_LE(file.filename().string().size(), 255u);
    EXPECT_EQ(file.parent_path(), dir);
    EXPECT_EQ(lockError(output, {1}), "");
}
