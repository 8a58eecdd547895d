// `ridge tiles` as a user runs it: a PMTiles file and a directory with a report, and bad
// options and outputs refused with the usage status or a message naming the path.
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>

TEST(TilesCli, WritesPmtilesAndDirectoriesAndRefusesBadRequests)
{
    const ridge::test::ScratchDir dir;
    const std::string archive =
        ridge::test::buildEverestWithCli(dir, "everest.ridge", "--patch 33");
    const auto json = ridge::test::runRidgeStdout("tiles " + archive + " -o " +
                                                  dir.path("e.pmtiles") + " --json");
    ASSERT_EQ(json.exit_code, 0) << json.output;
    const nlohmann::json report = nlohmann::json::parse(json.output);
    EXPECT_GT(report["tiles"].get<int>(), 10);
    EXPECT_EQ(report["maxzoom"], 11);
    EXPECT_EQ(report["output_bytes"].get<uint64_t>(),
              std::filesystem::file_size(dir.path("e.pmtiles")));
    const auto rgb = ridge::test::runRidge("tiles " + archive + " -o " + dir.path("rgb") +
                                           " --format terrain-rgb --image webp --maxzoom 9 -q");
    ASSERT_EQ(rgb.exit_code, 0) << rgb.output;
    EXPECT_TRUE(std::filesystem::exists(dir.path("rgb/tiles.json")));
    EXPECT_TRUE(std::filesystem::exists(dir.path("rgb/9/379/214.webp")));

    for (const std::string options : {"--format heightmap", "--size 300", "--maxzoom 29",
                                      "--minzoom -1", "--threads 0", "--cells 0", "--image jpeg"}) {
        const auto r = ridge::test::runRidge("tiles " + archive + " -o " + dir.path("x.pmtiles") +
                                             " " + options);
        EXPECT_EQ(r.exit_code, 2) << options << ": " << r.output;
    }
    const auto exists = ridge::test::runRidge("tiles " + archive + " -o " + dir.path("rgb"));
    EXPECT_EQ(exists.exit_code, 1);
    EXPECT_NE(exists.output.find("exists"), std::string::npos) << exists.output;
    const auto over = ridge::test::runRidge("tiles " + archive + " -o " + archive);
    EXPECT_EQ(over.exit_code, 1);
    const auto deep = ridge::test::runRidge("tiles " + archive + " -o " + dir.path("d.pmtiles") +
                                            " --maxzoom 14");
    EXPECT_EQ(deep.exit_code, 1);
    EXPECT_NE(deep.output.find("zoom 0 to 11"), std::string::npos) << deep.output;
    EXPECT_FALSE(std::filesystem::exists(dir.path("d.pmtiles")));
    EXPECT_FALSE(std::filesystem::exists(dir.path("x.pmtiles")));
}
