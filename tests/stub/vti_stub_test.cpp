// The .vti writer and reader of a build without VTK (src/io/vtk_export_stub.cpp), compiled
// into an executable of its own since the test suites link the real ones: each ends in one
// line naming the file, that VTK is missing and how to get it.
#include "base/error.h"
#include "io/vtk_export.h"

#include <gtest/gtest.h>

#include <string>

namespace {

std::string messageOf(void (*call)()) {
    try {
        call();
    } catch (const veil::Error& e) {
        return e.what();
    }
    return "(no error)";
}

void expectStubMessage(const std::string& m) {
    EXPECT_NE(m.find("'out/grid.vti'"), std::string::npos) << m;
    EXPECT_NE(m.find("built without VTK"), std::string::npos) << m;
    EXPECT_NE(m.find("scripts/install-deps.sh --test"), std::string::npos) << m;
    EXPECT_NE(m.find("libvtk9-dev"), std::string::npos) << m;
    EXPECT_NE(m.find("rebuild"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

TEST(VtiStub, NotSupported) { EXPECT_FALSE(veil::io::vtiSupported()); }

TEST(VtiStub, WriteNamesFileAndFix) {
    expectStubMessage(messageOf([] {
        veil::io::DenseGrid g;
        g.dims = {1, 1, 1};
        g.values = {1.0f};
        veil::io::writeVti("out/grid.vti", g);
    }));
}

TEST(VtiStub, ReadAndRequireNameFileAndFix) {
    expectStubMessage(messageOf([] { veil::io::readVti("out/grid.vti"); }));
    expectStubMessage(messageOf([] { veil::io::requireVti("out/grid.vti"); }));
}

} // namespace
