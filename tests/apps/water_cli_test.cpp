// The command line of water flags (issue 22): `build --sea-level M|none` and `--water FILE`,
// their refusals, and what `info` says of the water an archive stores.
#include "test_support.h"

#include <gtest/gtest.h>

using namespace ridge;

namespace {

std::string coast() { return test::dataPath("sfbay_coast.tif"); }

} // namespace

TEST(WaterCli, InfoStatesTheWaterSamplesAndTheRuleThatMadeThem)
{
    test::ScratchDir dir;
    const std::string arc = dir.path("coast.ridge");
    test::CommandResult r = test::runRidge("build '" + coast() + "' -o '" + arc +
                                           "' --codec progressive --max-error 1 --water '" +
                                           test::dataPath("crystal_springs_utm10.geojson") + "' -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = test::runRidge("info '" + arc + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("Water: 37293 samples (37.4 %), at or below 0 m, and the layer "),
              std::string::npos)
        << r.output;
    r = test::runRidge("build '" + coast() + "' -o '" + dir.path("dry.ridge") + "' --sea-level none -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = test::runRidge("info '" + dir.path("dry.ridge") + "'");
    EXPECT_NE(r.output.find("Water: 0 samples (0.0 %), no sea level"), std::string::npos) << r.output;
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
    const test::CommandResult r = test::runRidge("build '" + coast() + "' -o '" +
                                                 dir.path("x.ridge") + "' --water '" + missing + "'");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(missing), std::string::npos) << r.output;
    EXPECT_TRUE(test::namesIn(dir.dir()).empty());
}

TEST(WaterCli, TheWaterLayerIsAnInputNoOutputMayReplace)
{
    test::ScratchDir dir;
    const std::string lake = dir.path("lake.geojson");
    ASSERT_EQ(test::runShell("cp '" + test::dataPath("crystal_springs_utm10.geojson") + "' '" + lake + "'").exit_code, 0);
    const test::CommandResult r =
        test::runRidge("build '" + coast() + "' -o '" + lake + "' --water '" + lake + "'");
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_EQ(test::readFile(lake), test::readFile(test::dataPath("crystal_springs_utm10.geojson")));
}
