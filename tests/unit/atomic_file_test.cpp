// Atomic writes (base/atomic_file.h) under hostile conditions: a full file
// system, a writer that ignores its own write errors (as OpenVDB's File::write does), a
// file name near NAME_MAX, SIGTERM in the middle of a write, outputs that would overwrite an
// input, and a link planted at the temporary's name or swapped in for it.
#include "base/atomic_file.h"
#include "base/error.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {

fs::path testDir(const std::string& name) {
    const fs::path dir = fs::path(VEIL_TEST_OUTPUT_DIR) / "atomic_file_test" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// Names in `dir` that look like a temporary of writeFileAtomically.
std::vector<std::string> temporaries(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().find(".tmp") != std::string::npos)
            out.push_back(e.path().filename().string());
    return out;
}

// A 64 KiB tmpfs at `dir`, filled to the last block; unmounted on destruction.
class FullFileSystem {
public:
    explicit FullFileSystem(const fs::path& dir) : dir_(dir) {
        if (::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=64k") != 0) {
            reason_ = std::strerror(errno);
            return;
        }
        mounted_ = true;
        std::ofstream fill(dir / "fill", std::ios::binary);
        const std::string block(4096, 'f');
        for (int i = 0; i < 64 && fill.write(block.data(), block.size()); ++i) {
        }
    }
    ~FullFileSystem() {
        if (mounted_) ::umount(dir_.c_str());
    }
    bool mounted() const { return mounted_; }
    const std::string& reason() const { return reason_; }

private:
    fs::path dir_;
    bool mounted_ = false;
    std::string reason_;
};

} // namespace

// A 249-byte name is legal (NAME_MAX 255); ".<stem>.tmp<pid><ext>" was not, so the write
// failed with a rename error after the work was done.
TEST(AtomicFileTest, LongFileNameUsesShortTemporary) {
    const fs::path dir = testDir("long");
    const fs::path path = dir / (std::string(245, 'n') + ".png");
    ASSERT_EQ(path.filename().string().size(), 249u);
    const fs::path tmp = veil::temporaryPathFor(path);
    EXPECT_LE(tmp.filename().string().size(), 255u);
    EXPECT_EQ(tmp.extension(), ".png");
    EXPECT_EQ(tmp.parent_path(), dir);
    EXPECT_NE(veil::temporaryPathFor(dir / (std::string(245, 'm') + ".png")), tmp);
    veil::writeFileAtomically(path, [](const fs::path& t) { std::ofstream(t) << "image"; });
    EXPECT_TRUE(fs::exists(path));
    EXPECT_TRUE(temporaries(dir).empty());
    // Short names keep the readable form, with a random tag: ".a.tmp<pid>-<10 random>.json".
    const std::string shortName = veil::temporaryPathFor(dir / "a.json").filename().string();
    const std::string head = ".a.tmp" + std::to_string(::getpid()) + "-";
    EXPECT_EQ(shortName.substr(0, head.size()), head);
    EXPECT_EQ(shortName.size(), head.size() + 10 + 5) << shortName;
    EXPECT_EQ(shortName.substr(shortName.size() - 5), ".json");
}

// A link planted at the temporary name a write would use (before: ".<stem>.tmp<pid><ext>",
// known in advance) is never written through: the temporary has a random name and is created
// with O_EXCL | O_NOFOLLOW before the writer opens it.
TEST(AtomicFileTest, PlantedLinkAtTheTemporaryNameIsNotFollowed) {
    const fs::path dir = testDir("planted");
    const fs::path victim = dir / "victim.txt";
    std::ofstream(victim) << "keep";
    const fs::path planted = dir / (".out.tmp" + std::to_string(::getpid()) + ".exr");
    fs::create_symlink(victim, planted);
    fs::path seen;
    veil::writeFileAtomically(dir / "out.exr", [&](const fs::path& t) {
        seen = t;
        // Made before the writer runs: a regular, empty file of its own.
        EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(t)));
        EXPECT_EQ(fs::file_size(t), 0u);
        std::ofstream(t) << "image";
    });
    std::string text;
    std::ifstream(victim) >> text;
    EXPECT_EQ(text, "keep");
    std::ifstream(dir / "out.exr") >> text;
    EXPECT_EQ(text, "image");
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(dir / "out.exr")));
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(planted))) << "the planted link was touched";
    EXPECT_NE(seen, planted);
    // Two writes of one path draw different names.
    EXPECT_NE(veil::temporaryPathFor(dir / "out.exr"), veil::temporaryPathFor(dir / "out.exr"));
}

// A temporary replaced by a link while the writer runs (a race in a folder others can write)
// is refused, not renamed into place: the output would be a link to another file.
TEST(AtomicFileTest, TemporaryReplacedDuringTheWriteIsRefused) {
    const fs::path dir = testDir("replaced");
    const fs::path victim = dir / "victim.txt";
    std::ofstream(victim) << "keep";
    const fs::path out = dir / "out.vti";
    try {
        veil::writeFileAtomically(out, [&](const fs::path& t) {
            fs::remove(t);
            fs::create_symlink(victim, t);
        });
        ADD_FAILURE() << "a temporary replaced by a link was renamed into place";
    } catch (const veil::Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find(out.string()), std::string::npos) << m;
        EXPECT_NE(m.find("was replaced"), std::string::npos) << m;
    }
    EXPECT_FALSE(fs::exists(fs::symlink_status(out)));
    EXPECT_TRUE(temporaries(dir).empty());
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(victim)));
}

// On a full disk a checked writer fails, and an unchecked one (a short file is all it
// leaves) fails too; before, the empty or short file was renamed into place.
TEST(AtomicFileTest, FullFileSystemFailsAndLeavesNothing) {
    const fs::path dir = testDir("full");
    FullFileSystem full(dir);
    if (!full.mounted())
        GTEST_SKIP() << "cannot mount a tmpfs at " << dir << " (" << full.reason()
                     << "): run as root to test a full file system";
    const std::string text(100000, 'r');
    const fs::path report = dir / "report.json";
    try {
        veil::writeTextFileAtomically(report, text);
        ADD_FAILURE() << "writing 100 kB to a full 64 KiB file system succeeded";
    } catch (const veil::Error& e) {
        EXPECT_NE(std::string(e.what()).find(report.string()), std::string::npos) << e.what();
    }
    const fs::path vdb = dir / "grid.vdb";
    const auto ignoresErrors = [&](const fs::path& t) {
        std::ofstream out(t, std::ios::binary);
        out << text; // no check, like OpenVDB's File::write
    };
    EXPECT_THROW(veil::writeFileAtomically(vdb, ignoresErrors), veil::Error);
    // With room for part of the file: a short file and a full disk.
    fs::resize_file(dir / "fill", 32768);
    EXPECT_THROW(veil::writeFileAtomically(vdb, ignoresErrors), veil::Error);
    EXPECT_FALSE(fs::exists(report));
    EXPECT_FALSE(fs::exists(vdb));
    EXPECT_TRUE(temporaries(dir).empty());
}

TEST(AtomicFileTest, WriterThatWritesNothingFails) {
    const fs::path dir = testDir("empty");
    EXPECT_THROW(veil::writeFileAtomically(dir / "a.vti", [](const fs::path&) {}), veil::Error);
    EXPECT_THROW(
        veil::writeFileAtomically(dir / "b.vti", [](const fs::path& t) { std::ofstream{t}; }),
        veil::Error);
    EXPECT_TRUE(fs::is_empty(dir));
}

// SIGTERM while the temporary exists: the handler unlinks it and the process still dies
// of SIGTERM (so a shell sees 143). Before, ".<stem>.tmp<pid><ext>" stayed behind.
TEST(AtomicFileTest, SigtermDuringWriteRemovesTheTemporary) {
    for (int sig : {SIGTERM, SIGINT}) {
        const fs::path dir = testDir("signal" + std::to_string(sig));
        int ready[2];
        ASSERT_EQ(::pipe(ready), 0);
        const pid_t child = ::fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            ::signal(sig, SIG_DFL);
            veil::installTemporaryFileCleanup();
            veil::writeFileAtomically(dir / "out.exr", [&](const fs::path& t) {
                std::ofstream(t) << "partial";
                const char c = 'r';
                (void)!::write(ready[1], &c, 1);
                ::pause(); // a slow writer
            });
            ::_exit(0);
        }
        char c = 0;
        ASSERT_EQ(::read(ready[0], &c, 1), 1);
        EXPECT_EQ(temporaries(dir).size(), 1u);
        ::kill(child, sig);
        int status = 0;
        ASSERT_EQ(::waitpid(child, &status, 0), child);
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << status;
        EXPECT_TRUE(temporaries(dir).empty());
        EXPECT_FALSE(fs::exists(dir / "out.exr"));
        ::close(ready[0]);
        ::close(ready[1]);
    }
}

TEST(AtomicFileTest, OutputPathsAreCheckedBeforeWork) {
    const fs::path dir = testDir("check");
    const fs::path scene = dir / "scene.json";
    std::ofstream(scene) << "{}";
    const auto message = [](const auto& f) -> std::string {
        try {
            f();
        } catch (const veil::Error& e) {
            return e.what();
        }
        return "no error";
    };
    EXPECT_NE(
        message([&] { veil::checkOutputPath(dir / "no/such/r.json", "report"); }).find("folder"),
        std::string::npos);
    EXPECT_NE(message([&] { veil::checkOutputPath(dir, "output"); }).find("folder"),
              std::string::npos);
    EXPECT_NE(message([&] {
                  veil::checkOutputPath(scene, "output", {scene});
              }).find("would overwrite the input"),
              std::string::npos);
    EXPECT_NE(message([&] {
                  veil::checkOutputPath(dir / ".." / "check" / "scene.json", "output", {scene});
              }).find("would overwrite the input"),
              std::string::npos);
    EXPECT_NE(
        message([&] { veil::checkOutputPath(dir / std::string(256, 'x'), "output"); }).find("255"),
        std::string::npos);
    EXPECT_NO_THROW(veil::checkOutputPath(dir / "new.png", "output", {scene}));
    EXPECT_NO_THROW(veil::checkOutputPath(dir / (std::string(251, 'x') + ".png"), "output"));
}
