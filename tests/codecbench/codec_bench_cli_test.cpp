// `ridge codec-bench` as a user runs it.
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

using namespace ridge;
namespace fs = std::filesystem;

TEST(CodecBenchCli, WritesTablesJsonAndPlot)
{
    test::ScratchDir dir;
    const std::string json = dir.path("bench.json");
    const std::string png = dir.path("bench.png");
    // Defaults: ridge's progressive codec, built with max_error = 1 m.
    const test::CommandResult r =
        test::runRidge("codec-bench '" + test::dataPath("everest_crop.tif") +
                       "' --max-error 1 --tile 64 --json-file '" + json + "' --plot '" + png + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("100 - done."), std::string::npos) << "progress on stderr";
    EXPECT_EQ(r.output.find("VIOLATED"), std::string::npos) << r.output;
    for (const char* name :
         {"ridge progressive", "LERC", "JPEG-LS", "JPEG 2000", "JPEG XL e7", "JPEG XL e9",
          "JPEG XL e9 progressive", "MED+zstd", "ZFP",
          "ridge progressive: bytes fetched per view at 1920×1080, ε = 2 px: near "})
        EXPECT_NE(r.output.find(name), std::string::npos) << name;
    ASSERT_TRUE(fs::exists(json));
    ASSERT_TRUE(fs::exists(png));
    std::ifstream in(json);
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["bounds"].size(), 1u);
    EXPECT_EQ(j["bounds"][0]["rows"].size(), 9u);
    EXPECT_TRUE(j["bounds"][0]["rows"][0]["bound_ok"].get<bool>());
    EXPECT_GT(j["bounds"][0]["rows"][0]["view_bytes"]["far"]["bytes"].get<uint64_t>(), 0u);
    EXPECT_EQ(test::temporariesIn(dir.dir()), std::vector<std::string>{});
}

namespace {

// `codec-bench` of the fixture at 4 m with --json and `flags`: its stdout parsed, which
// fails unless the document is all there is (null when the command failed).
nlohmann::json benchJsonOnStdout(const std::string& flags)
{
    const test::CommandResult r =
        test::runRidgeStdout("codec-bench '" + test::dataPath("everest_crop.tif") +
                             "' --max-error 4 --tile 64 -q --json" + flags);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return r.exit_code == 0 ? nlohmann::json::parse(r.output) : nlohmann::json();
}

} // namespace

// --json: the same document on stdout and nothing else there (the tables go to stderr).
TEST(CodecBenchCli, JsonPrintsTheDocumentOnStdout)
{
    const nlohmann::json j = benchJsonOnStdout("");
    EXPECT_EQ(j["bounds"].size(), 1u);
    EXPECT_EQ(j["bounds"][0]["rows"].size(), 9u);
}

// --overviews: a second row per single-level anchor (not JPEG XL progressive, a pyramid
// already), with the fixture's one overview at gdaladdo's 256-sample minimum (301 x 203 ->
// 151 x 102).
TEST(CodecBenchCli, OverviewsAddARowPerAnchor)
{
    const nlohmann::json j = benchJsonOnStdout(" --overviews");
    ASSERT_EQ(j["overview_sizes"].size(), 1u);
    EXPECT_EQ(j["overview_sizes"][0]["width"], 151);
    EXPECT_EQ(j["overview_sizes"][0]["height"], 102);
    const nlohmann::json& rows = j["bounds"][0]["rows"];
    ASSERT_EQ(rows.size(), 16u);
    EXPECT_EQ(rows[9]["codec"], "LERC + overviews");
    EXPECT_EQ(rows[14]["codec"], "MED+zstd + overviews") << "no JPEG XL progressive + overviews";
    EXPECT_EQ(rows[15]["codec"], "ZFP + overviews");
    EXPECT_EQ(rows[15]["scope"], "with overviews");
}

TEST(CodecBenchCli, MissingInputFailsNamingThePath)
{
    test::ScratchDir dir;
    const std::string missing = dir.path("missing.hgt");
    const std::string json = dir.path("bench.json");
    const test::CommandResult r = test::runRidge("codec-bench '" + missing + "' --json-file '" +
                                                 json + "' -q --ridge-codec lossless");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.output.find(missing), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(json));
}

TEST(CodecBenchCli, NegativeBoundIsAParseError)
{
    const test::CommandResult r = test::runRidge(
        "codec-bench '" + test::dataPath("everest_crop.tif") + "' --max-error -1 -q");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.output.find("max-error"), std::string::npos) << r.output;
}
