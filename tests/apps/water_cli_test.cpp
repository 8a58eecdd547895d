// The command line of water flags (issue 22): `build --sea-level M|none` and `--water FILE`,
// their refusals, and what `info` says of the water an archive stores.
#include "test_support.h"

#include <gtest/gtest.h>

using namespace ridge;

namespace {

std::string coast()
{
    return test::dataPath("sfbay_coast.tif");
}

} // namespace

TEST(WaterCli, InfoStatesTheWaterSamplesAndTheRuleThatMadeThem)
{
    test::ScratchDir dir;
    const std::string arc = dir.path("coast.ridge");
    test::CommandResult r = test::runRidge(
        "build '" + coast() + "' -o '" + arc + "' --codec progressive --max-error 1 --water '" +
        test::dataPath("crystal_springs_utm10.geojson") + "' -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = test::runRidge("info '" + arc + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("Water: 37293 samples (37.4 %), at or below 0 m, and the layer "),
              std::string::npos)
        << r.output;
    r = test::runRidge("build '" + coast() + "' -o '" + dir.path("dry.ridge") +
                       "' --sea-level none -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = test::runRidge("info '" + dir.path("dry.ridge") + "'");
    EXPECT_NE(r.output.find("Water: 0 samples (0.0 %), no sea level"), std::string::npos)
        << r.output;
}

TEST(WaterCli, ABadSeaLevelIsAUsageErrorBeforeAnyWork)
{
    test::ScratchDir dir;
    for (const char* bad : {"nan", "1e9", "low", "inf"}) {
        const test::CommandResult r = test::runRidge("build '" + coast() + "' -o '" +
                                                     dir.path("x.ridge") + "' --sea-level " + bad);
        EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.output;
        EXPECT_NE(r.output.find("--sea-level"), std::string::npos) << r.output;
        EXPECT_EQ(r.output.find("0..."), std::string::npos) << "no progress: " << r.output;
    }
}

TEST(WaterCli, AMissingWaterLayerFailsNamingItAndLeavesNoOutput)
{
    test::ScratchDir dir;
    const std::string missing = dir.path("no_such_lakes.shp");
    const test::CommandResult r = test::runRidge(
        "build '" + coast() + "' -o '" + dir.path("x.ridge") + "' --water '" + missing + "'");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(missing), std::string::npos) << r.output;
    EXPECT_TRUE(test::namesIn(dir.dir()).empty());
}

TEST(WaterCli, TheWaterLayerIsAnInputNoOutputMayReplace)
{
    test::ScratchDir dir;
    const std::string lake = dir.path("lake.geojson");
    ASSERT_EQ(test::runShell("cp '" + test::dataPath("crystal_springs_utm10.geojson") + "' '" +
                             lake + "'")
                  .exit_code,
              0);
    const test::CommandResult r =
        test::runRidge("build '" + coast() + "' -o '" + lake + "' --water '" + lake + "'");
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_EQ(test::readFile(lake),
              test::readFile(test::dataPath("crystal_springs_utm10.geojson")));
}

TEST(WaterCli, QueryMarksWaterAndFilledAnswers)
{
    test::ScratchDir dir;
    const std::string arc = dir.path("coast.ridge");
    ASSERT_EQ(test::runRidge("build '" + coast() + "' -o '" + arc +
                             "' --codec progressive --max-error 1 -q")
                  .exit_code,
              0);
    // Pixel (270.5, 100.5) is the Bay at 0 m, (150.5, 250.5) the peninsula's hills (135 m).
    test::CommandResult r = test::runRidge("query '" + arc + "' --pixel 270.5 100.5");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("; water)"), std::string::npos) << r.output;
    r = test::runRidge("query '" + arc + "' --pixel 150.5 250.5");
    EXPECT_EQ(r.output.find("water"), std::string::npos) << r.output;
    r = test::runRidgeStdout("query '" + arc + "' --pixel 270.5 100.5 --json");
    EXPECT_NE(r.output.find("\"water\": true"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\"filled\": false"), std::string::npos) << r.output;

    const std::string voids = dir.path("rainier.ridge");
    ASSERT_EQ(test::runRidge("build '" + test::dataPath("rainier_voids.tif") + "' -o '" + voids +
                             "' --fill-voids all -q")
                  .exit_code,
              0);
    // Sample (226, 8) is a raw-SRTM void of the Rainier fixture: its height is
    // GDALFillNodata's, not a measurement; (100, 100) is measured.
    r = test::runRidge("query '" + voids + "' --pixel 226.5 8.5");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("filled: a void of the source"), std::string::npos) << r.output;
    r = test::runRidge("query '" + voids + "' --pixel 100.5 100.5");
    EXPECT_EQ(r.output.find("filled"), std::string::npos) << r.output;
}
