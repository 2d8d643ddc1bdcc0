// The build's provenance (src/io/provenance.h, cmake/git_commit.cmake): the commit in
// `--version`'s line and in every image header; the generator names `git describe` of a
// checkout and says "unknown" for a tree without .git; a failed image write on a full file
// system names the file and "no space left on device".
#include "io/image_io.h"
#include "io/provenance.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <map>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

// The header cmake/git_commit.cmake writes for `source`.
std::string generatedHeader(const fs::path& source, const std::string& name) {
    const fs::path out = freshOutputDir("provenance", name) / "version_info.h";
    const CommandResult r = runCommand("cmake -DSOURCE_DIR=" + shellQuote(source) + " -DTEMPLATE=" +
                                       shellQuote(sourceDir() / "src/app/version_info.h.in") +
                                       " -DOUTPUT=" + shellQuote(out) + " -DVERSION=9.8.7 -P " +
                                       shellQuote(sourceDir() / "cmake/git_commit.cmake"));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return readTextFile(out);
}

} // namespace

TEST(ProvenanceTest, VersionLineNamesTheCommit) {
    EXPECT_FALSE(io::gitCommit().empty());
    EXPECT_EQ(io::versionLine().rfind(io::veilVersion() + " (commit " + io::gitCommit(), 0), 0u)
        << io::versionLine();
    EXPECT_EQ(io::gitTreeDirty(), io::gitCommit().ends_with("-dirty"));
    std::map<std::string, std::string> a;
    for (const auto& [k, v] : io::provenanceAttributes())
        a[k] = v;
    EXPECT_EQ(a["veil:commit"], io::gitCommit());
    EXPECT_EQ(a["veil:version"], io::veilVersion());
}

TEST(ProvenanceTest, GeneratorUsesGitDescribeOrSaysUnknown) {
    // A tree without .git (a tarball): "unknown".
    const fs::path tarball = freshOutputDir("provenance", "tarball-tree");
    std::string h = generatedHeader(tarball, "tarball");
    EXPECT_NE(h.find("#define VEIL_GIT_COMMIT \"unknown\""), std::string::npos) << h;
    EXPECT_NE(h.find("#define VEIL_GIT_DIRTY 0"), std::string::npos) << h;
    EXPECT_NE(h.find("#define VEIL_VERSION_TEXT \"9.8.7\""), std::string::npos) << h;
    // This checkout: what git describe says.
    if (!fs::exists(sourceDir() / ".git")) GTEST_SKIP() << "no .git in the source tree";
    const CommandResult d =
        runCommand("git -C " + shellQuote(sourceDir()) + " describe --always --dirty --abbrev=12");
    ASSERT_EQ(d.exitCode, 0) << d.output;
    const std::string described = d.output.substr(0, d.output.find('\n'));
    h = generatedHeader(sourceDir(), "checkout");
    EXPECT_NE(h.find("#define VEIL_GIT_COMMIT \"" + described + "\""), std::string::npos) << h;
}

TEST(ProvenanceTest, FullDiskWriteFailureNamesFileAndCause) {
    const fs::path p = outputSubdir("provenance") / "full.exr";
    const std::string full =
        io::describeWriteFailure(p, "Failed OpenEXR write: File output failed.", ENOSPC);
    EXPECT_NE(full.find("cannot write '" + p.string() + "'"), std::string::npos) << full;
    EXPECT_NE(full.find("no space left on device"), std::string::npos) << full;
    EXPECT_NE(full.find("File output failed"), std::string::npos) << full;
    EXPECT_NE(io::describeWriteFailure(p, "x", EDQUOT).find("no space left"), std::string::npos);
    // Any other failure keeps the library's words (this disk has room).
    const std::string other = io::describeWriteFailure(p, "bad channel", EINVAL);
    EXPECT_EQ(other, "cannot write '" + p.string() + "': bad channel");
    EXPECT_EQ(io::describeWriteFailure(p, "", 0),
              "cannot write '" + p.string() + "': the image writer failed");
}

TEST(ProvenanceTest, EveryImageWrittenCarriesTheCommit) {
    ImageF img(4, 2, 3);
    for (const char* name : {"p.png", "p.exr"}) {
        const fs::path p = outputSubdir("provenance") / name;
        io::writeImage(p, img, true, {{"veil:case", "c1"}});
        std::map<std::string, std::string> a;
        for (const auto& [k, v] : io::readImageAttributes(p))
            a[k] = v;
        EXPECT_EQ(a["veil:commit"], io::gitCommit()) << name;
        EXPECT_EQ(a["veil:version"], io::veilVersion()) << name;
        EXPECT_EQ(a["veil:case"], "c1") << name;
    }
}

} // namespace veil::test
