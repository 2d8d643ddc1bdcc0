// The "did you mean" helper of the veil command (src/base/suggest.h).
#include "base/suggest.h"

#include <gtest/gtest.h>

namespace veil {

TEST(SuggestTest, EditDistanceCountsInsertionsDeletionsSubstitutions) {
    EXPECT_EQ(editDistance("", ""), 0u);
    EXPECT_EQ(editDistance("abc", ""), 3u);
    EXPECT_EQ(editDistance("", "ab"), 2u);
    EXPECT_EQ(editDistance("render", "render"), 0u);
    EXPECT_EQ(editDistance("rendr", "render"), 1u);    // one insertion
    EXPECT_EQ(editDistance("--widht", "--width"), 2u); // a swap is two substitutions
    EXPECT_EQ(editDistance("kitten", "sitting"), 3u);  // the textbook pair
    EXPECT_EQ(editDistance("sitting", "kitten"), 3u);  // symmetric
    EXPECT_EQ(editDistance("flaw", "lawn"), 2u);
}

TEST(SuggestTest, NearestWordOnlyForTypos) {
    const std::vector<std::string> commands{"render", "info", "view", "voxelize", "techniques"};
    EXPECT_EQ(nearestWord("rendr", commands), "render");
    EXPECT_EQ(nearestWord("infp", commands), "info");
    EXPECT_EQ(nearestWord("voxelise", commands), "voxelize");
    EXPECT_EQ(nearestWord("xyzzy", commands), "");
    EXPECT_EQ(nearestWord("", commands), "");
    EXPECT_EQ(nearestWord("--widht", {"--width", "--height", "--camera"}), "--width");
}

} // namespace veil
