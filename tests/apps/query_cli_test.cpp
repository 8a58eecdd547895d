// `ridge query`, the geographic camera options and `ridge info`'s corners as a user runs them,
// against GDAL's own reads and gdalinfo's output.
#include "test_support.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <sstream>

using namespace ridge;

namespace {

std::string quoted(const std::string& path)
{
    std::string q = "'";
    q += path;
    q += "'";
    return q;
}

// stdout only (the CLI's stderr notes dropped), for JSON.
test::CommandResult runStdout(const std::string& args)
{
    return test::runShell("{ " + std::string(RIDGE_CLI_PATH) + " " + args + " 2>/dev/null; }");
}

std::vector<double> readSource(const std::string& path, int& width, int& height)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
    EXPECT_NE(ds, nullptr);
    width = GDALGetRasterXSize(ds);
    height = GDALGetRasterYSize(ds);
    std::vector<double> v(size_t(width) * height);
    EXPECT_EQ(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, 0, 0, width, height, v.data(), width,
                           height, GDT_Float64, 0, 0),
              CE_None);
    GDALClose(ds);
    return v;
}

std::string buildArchive(const test::ScratchDir& dir, const std::string& source,
                         const std::string& name)
{
    const std::string arc = dir.path(name);
    const test::CommandResult r = test::runRidge("build " + quoted(test::dataPath(source)) +
                                                 " -o " + quoted(arc) + " -q --patch 33");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return arc;
}

// The "Corner Coordinates:" block of a gdalinfo-style text output.
std::string cornerBlock(const std::string& text)
{
    const size_t start = text.find("Corner Coordinates:");
    if (start == std::string::npos)
        return {};
    size_t end = start;
    for (int line = 0; line < 6 && end != std::string::npos; ++line)
        end = text.find('\n', end + 1);
    return text.substr(start, end - start);
}

} // namespace

TEST(QueryCli, BatchFromStdinEchoesEachPointAndExitsOneForOffRasterPoints)
{
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir, "everest_crop.tif", "e.ridge");
    int w = 0, h = 0;
    const std::vector<double> src = readSource(test::dataPath("everest_crop.tif"), w, h);
    // Pixel centres of a lossless archive: GDAL's values exactly.
    std::ostringstream input;
    for (int k = 0; k < 20; ++k)
        input << (k * 37 % w) + 0.5 << " " << (k * 23 % h) + 0.5 << "\n";
    const test::CommandResult ok = test::runShell(
        "printf '" + input.str() + "' | " + RIDGE_CLI_PATH + " query --pixel " + quoted(arc));
    ASSERT_EQ(ok.exit_code, 0) << ok.output;
    std::istringstream lines(ok.output);
    std::string line;
    int k = 0;
    for (; std::getline(lines, line) && k < 20; ++k) {
        const int c = k * 37 % w, r = k * 23 % h;
        double value = NAN;
        char echo[64];
        std::snprintf(echo, sizeof echo, "%d.5 %d.5: ", c, r);
        ASSERT_EQ(line.rfind(echo, 0), 0u) << "echo: " << line;
        ASSERT_EQ(std::sscanf(line.c_str() + std::strlen(echo), "%lf m", &value), 1) << line;
        EXPECT_EQ(value, src[size_t(r) * w + c]) << line;
    }
    EXPECT_EQ(k, 20);

    // An off-raster point and a malformed line: notes, every other point answered, exit 1.
    const test::CommandResult mixed =
        test::runShell("printf '10.5 10.5\\n-3 10\\nten 10\\n\\n20.5 20.5\\n' | " +
                       std::string(RIDGE_CLI_PATH) + " query --pixel " + quoted(arc));
    EXPECT_EQ(mixed.exit_code, 1) << mixed.output;
    EXPECT_NE(mixed.output.find("-3 10: off the raster"), std::string::npos) << mixed.output;
    EXPECT_NE(mixed.output.find("ten 10: error: expected two numbers"), std::string::npos)
        << mixed.output;
    EXPECT_NE(mixed.output.find("20.5 20.5: "), std::string::npos) << mixed.output;
    EXPECT_NE(mixed.output.find("2 point(s) without a height"), std::string::npos)
        << mixed.output;
}

TEST(QueryCli, LonLatCrsAndJsonAgreeWithTheSource)
{
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir, "everest_crop.tif", "e.ridge");
    int w = 0, h = 0;
    const std::vector<double> src = readSource(test::dataPath("everest_crop.tif"), w, h);
    // 86.925 E, 27.988 N: column 210, row 14.4 (pixel 210.5, line 14.9): bilinear between
    // rows 14 and 15.
    const double expected = 0.6 * src[14 * size_t(w) + 210] + 0.4 * src[15 * size_t(w) + 210];
    for (const std::string& flags : {std::string("--lonlat"), std::string("")}) {
        const test::CommandResult r =
            runStdout("query " + flags + " --json " + quoted(arc) + " 86.925 27.988");
        ASSERT_EQ(r.exit_code, 0) << r.output;
        const nlohmann::json j = nlohmann::json::parse(r.output);
        ASSERT_EQ(j["points"].size(), 1u);
        const nlohmann::json& p = j["points"][0];
        EXPECT_TRUE(p["on_raster"].get<bool>());
        EXPECT_NEAR(p["height"].get<double>(), expected, 1e-6) << r.output;
        EXPECT_NEAR(p["pixel"][0].get<double>(), 210.5, 1e-6);
        EXPECT_NEAR(p["pixel"][1].get<double>(), 14.9, 1e-6);
    }
    const test::CommandResult off =
        runStdout("query --lonlat --json " + quoted(arc) + " 80 27.9");
    EXPECT_EQ(off.exit_code, 1);
    const nlohmann::json j = nlohmann::json::parse(off.output);
    EXPECT_FALSE(j["points"][0]["on_raster"].get<bool>());
    EXPECT_TRUE(j["points"][0]["height"].is_null());
    EXPECT_EQ(j["failed"].get<int>(), 1);
    // A coarser level's surface, and a level that does not exist.
    const test::CommandResult coarse =
        runStdout("query --json --level 1 " + quoted(arc) + " 86.925 27.988");
    ASSERT_EQ(coarse.exit_code, 0) << coarse.output;
    EXPECT_EQ(nlohmann::json::parse(coarse.output)["points"][0]["level"].get<int>(), 1);
    const test::CommandResult deep = test::runRidge("query --level 9 " + quoted(arc) + " 1 1");
    EXPECT_EQ(deep.exit_code, 1);
    EXPECT_NE(deep.output.find("level"), std::string::npos) << deep.output;
    const test::CommandResult half = test::runRidge("query " + quoted(arc) + " 86.9");
    EXPECT_NE(half.exit_code, 0);
    EXPECT_NE(half.output.find("both X and Y"), std::string::npos) << half.output;
}

TEST(InfoCli, CornersAreGdalinfos)
{
    test::ScratchDir dir;
    for (const std::string source : {"everest_crop.tif", "everest_utm45.tif"}) {
        const std::string arc = buildArchive(dir, source, source + ".ridge");
        const test::CommandResult gdal = test::runShell("gdalinfo " + quoted(test::dataPath(source)));
        if (gdal.exit_code != 0)
            GTEST_SKIP() << "gdalinfo is not installed";
        const test::CommandResult ours = test::runRidge("info " + quoted(arc));
        ASSERT_EQ(ours.exit_code, 0) << ours.output;
        const std::string expected = cornerBlock(gdal.output);
        ASSERT_FALSE(expected.empty());
        EXPECT_EQ(cornerBlock(ours.output), expected) << ours.output;

        const nlohmann::json gj = nlohmann::json::parse(
            test::runShell("gdalinfo -json " + quoted(test::dataPath(source))).output);
        const nlohmann::json rj = nlohmann::json::parse(runStdout("info --json " + quoted(arc)).output);
        const auto& ring = gj["wgs84Extent"]["coordinates"][0]; // UL, LL, LR, UR
        const char* keys[] = {"upperLeft", "lowerLeft", "lowerRight", "upperRight"};
        for (int k = 0; k < 4; ++k) {
            for (int axis = 0; axis < 2; ++axis) {
                EXPECT_NEAR(rj["cornerCoordinates"][keys[k]][axis].get<double>(),
                            gj["cornerCoordinates"][keys[k]][axis].get<double>(), 1e-3)
                    << source << " " << keys[k];
                // gdalinfo rounds the WGS 84 extent to 7 decimals.
                EXPECT_NEAR(rj["cornerLonLat"][keys[k]][axis].get<double>(),
                            ring[k][axis].get<double>(), 6e-8)
                    << source << " " << keys[k];
            }
        }
    }
}

TEST(RenderCli, AGeographicCameraIsPlacedThroughProj)
{
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir, "everest_crop.tif", "e.ridge");
    const test::CommandResult r = runStdout(
        "render " + quoted(arc) + " -o " + quoted(dir.path("g.png")) +
        " --size 64x36 --json --camera-lonlat 86.925,27.988,9500 --heading 200 --pitch -20");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(r.output);
    // Column 210 of 3" pixels ≈ 82.03 m apart, row 14.4 of ≈ 92.35 m rows from the north.
    const nlohmann::json info = nlohmann::json::parse(runStdout("info --json " + quoted(arc)).output);
    const double sx = info["spacing_x"].get<double>(), sy = info["spacing_y"].get<double>();
    EXPECT_NEAR(j["camera"][0].get<double>(), 210.0 * sx, 1e-3);
    EXPECT_NEAR(j["camera"][1].get<double>(), (202.0 - 14.4) * sy, 1e-3);
    EXPECT_EQ(j["camera"][2].get<double>(), 9500.0);
    EXPECT_NEAR(j["heading_deg"].get<double>(), -160.0, 1e-9);
    EXPECT_NEAR(j["pitch_deg"].get<double>(), -20.0, 1e-9);
    // Both forms of one thing, or a lon/lat camera without a CRS, are refused by name.
    const test::CommandResult both = test::runRidge(
        "render " + quoted(arc) + " -o " + quoted(dir.path("b.png")) +
        " --camera 1,2,3 --camera-lonlat 86.9,27.9,9000");
    EXPECT_NE(both.exit_code, 0);
    EXPECT_NE(both.output.find("--camera-lonlat"), std::string::npos) << both.output;
}

TEST(QueryCli, NegativeCoordinatesArePositionalNumbersNotFlags)
{
    test::ScratchDir dir;
    const test::CommandResult build = test::runRidge(
        "build " + quoted(test::dataPath("rainier_voids.tif")) + " -o " +
        quoted(dir.path("r.ridge")) + " -q --patch 33");
    ASSERT_EQ(build.exit_code, 0) << build.output;
    const test::CommandResult r =
        runStdout("query --lonlat --json " + quoted(dir.path("r.ridge")) + " -121.5 46.7");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j["points"][0]["input"].get<std::string>(), "-121.5 46.7");
    EXPECT_TRUE(j["points"][0]["on_raster"].get<bool>());
    EXPECT_GT(j["points"][0]["height"].get<double>(), 347.0); // the crop's range: 347..1994 m
    EXPECT_LT(j["points"][0]["height"].get<double>(), 1994.0);
}
