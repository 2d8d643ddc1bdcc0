// The frame's pass list (src/frame/pass_list.h): a read with no earlier writer is an error
// naming the pass and the resource; the frame the renderer builds passes its own check.
#include "base/error.h"
#include "frame/pass_list.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

namespace veil::frame {
namespace {

std::string validationError(const PassList& list, const std::vector<std::string>& external = {}) {
    return test::errorOf([&] { list.validate(external); });
}

PassList frameLike() {
    PassList l;
    l.add({"shadow", {}, {"shadow.0"}, {}})
        .add({"opaque", {"shadow.0"}, {"depth", "hdr"}, {}})
        .add({"fog", {"depth", "shadow.0"}, {"fog.radiance"}, {}})
        .add({"transparent", {"depth", "fog.radiance"}, {"oit.accumulation"}, {}})
        .add({"resolve", {"oit.accumulation", "hdr"}, {"hdr"}, {}})
        .add({"tonemap", {"hdr"}, {"ldr"}, {}});
    return l;
}

TEST(PassListTest, WellOrderedFrameValidates) {
    const PassList l = frameLike();
    EXPECT_EQ(validationError(l), "");
    EXPECT_EQ(l.resources(), (std::vector<std::string>{"shadow.0", "depth", "hdr", "fog.radiance",
                                                       "oit.accumulation", "ldr"}));
    ASSERT_NE(l.find("fog"), nullptr);
    EXPECT_EQ(l.find("fog")->reads.size(), 2u);
    EXPECT_EQ(l.find("nope"), nullptr);
    EXPECT_NE(l.describe().find("opaque: shadow.0 -> depth, hdr"), std::string::npos)
        << l.describe();
}

TEST(PassListTest, ReadBeforeWriteNamesPassAndResource) {
    PassList l;
    l.add({"transparent", {"depth", "fog.radiance"}, {"oit.accumulation"}, {}})
        .add({"fog", {"depth"}, {"fog.radiance"}, {}});
    const std::string e = validationError(l, {"depth"});
    EXPECT_NE(e.find("pass 'transparent' reads 'fog.radiance', which no earlier pass writes"),
              std::string::npos)
        << e;
    EXPECT_NE(e.find("written so far: depth"), std::string::npos) << e;
    // Without the external depth the first read already fails.
    EXPECT_NE(validationError(l).find("reads 'depth'"), std::string::npos);
    // A missing shadow pass: opaque reads a shadow map nobody rendered.
    PassList noShadow;
    noShadow.add({"opaque", {"shadow.0"}, {"depth", "hdr"}, {}});
    EXPECT_NE(validationError(noShadow).find("'shadow.0'"), std::string::npos);
}

TEST(PassListTest, DuplicateAndEmptyNamesAreErrors) {
    PassList l = frameLike();
    l.add({"opaque", {}, {"hdr"}, {}});
    EXPECT_NE(validationError(l).find("two passes are named 'opaque'"), std::string::npos);
    PassList unnamed;
    unnamed.add({"", {}, {"x"}, {}});
    EXPECT_NE(validationError(unnamed).find("without a name"), std::string::npos);
}

} // namespace
} // namespace veil::frame
