#include "ridge/core/nearest_name.h"

#include <gtest/gtest.h>

using namespace ridge;

TEST(EditDistance, CountsInsertionsDeletionsSubstitutionsAndSwaps)
{
    EXPECT_EQ(editDistance("", ""), 0u);
    EXPECT_EQ(editDistance("", "abc"), 3u);
    EXPECT_EQ(editDistance("abc", ""), 3u);
    EXPECT_EQ(editDistance("build", "build"), 0u);
    EXPECT_EQ(editDistance("frams", "frames"), 1u);   // insertion
    EXPECT_EQ(editDistance("framess", "frames"), 1u); // deletion
    EXPECT_EQ(editDistance("frbmes", "frames"), 1u);  // substitution
    EXPECT_EQ(editDistance("biuld", "build"), 1u);    // adjacent swap
    EXPECT_EQ(editDistance("kitten", "sitting"), 3u); // Levenshtein's classic
    EXPECT_EQ(editDistance("ca", "abc"), 3u);         // OSA: no edit of a swapped pair
    EXPECT_EQ(editDistance("abc", "ca"), editDistance("ca", "abc"));
}

TEST(NearestName, SuggestsAPlausibleTypoAndNothingForAStranger)
{
    const std::vector<std::string> commands = {"build",     "info",   "verify", "extract",
                                               "hillshade", "render", "bench",  "view"};
    EXPECT_EQ(nearestName("biuld", commands), "build");
    EXPECT_EQ(nearestName("rendr", commands), "render");
    EXPECT_EQ(nearestName("verfiy", commands), "verify");
    EXPECT_EQ(nearestName("BUILD", commands), "build"); // case folded
    EXPECT_EQ(nearestName("frobnicate", commands), std::nullopt);
    EXPECT_EQ(nearestName("x", commands), std::nullopt);
    EXPECT_EQ(nearestName("", commands), std::nullopt);
    EXPECT_EQ(nearestName("build", {}), std::nullopt);
    EXPECT_EQ(nearestName("frams", {"frames", "fov", "size"}), "frames");
    EXPECT_EQ(nearestName("gtif", {"GTiff", "PNG", "COG"}), "GTiff");
}
