// The public API (<ridge/ridge.h>) through the shared library, as an embedding application
// sees it: only ridge.h is included and only libridge is linked (tests/CMakeLists.txt), so
// these tests also prove that the API is complete on its own and that ridge::Error crosses
// the library boundary.
#include <ridge/ridge.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

using ridge::test::dataPath;
using ridge::test::ScratchDir;

std::string everestArchive(const ScratchDir& dir, const std::string& codec = "lossless")
{
    ridge::BuildParameters p;
    p.codec = codec;
    p.patch_size = 33;
    if (codec == "progressive")
        p.max_error = 1.0;
    const std::string path = dir.path("everest-" + codec + ".ridge");
    ridge::build(dataPath("everest_crop.tif"), path, p);
    return path;
}

TEST(PublicApi, VersionMatchesTheHeader)
{
    const std::string expected = std::to_string(RIDGE_VERSION_MAJOR) + "." +
                                 std::to_string(RIDGE_VERSION_MINOR) + "." +
                                 std::to_string(RIDGE_VERSION_PATCH);
    EXPECT_EQ(ridge::versionString(), expected);
}

TEST(PublicApi, BuildOpenAndDescribe)
{
    ScratchDir dir;
    ridge::BuildParameters p;
    p.patch_size = 33;
    const std::string path = dir.path("everest.ridge");
    const ridge::BuildSummary built = ridge::build(dataPath("everest_crop.tif"), path, p);
    EXPECT_EQ(built.width, 301);
    EXPECT_EQ(built.height, 203);
    EXPECT_GT(built.patches, 1);
    EXPECT_EQ(built.archive_bytes, std::filesystem::file_size(path));

    const ridge::Terrain terrain(path);
    const ridge::TerrainInfo& info = terrain.info();
    EXPECT_EQ(info.width, 301);
    EXPECT_EQ(info.height, 203);
    EXPECT_EQ(info.levels, built.levels);
    EXPECT_EQ(info.patches, built.patches);
    EXPECT_EQ(info.patch_size, 33);
    EXPECT_EQ(info.codec, "lossless");
    EXPECT_EQ(info.max_error, 0.0); // Int16 source, lossless codec: exact
    // The fixture's summit (8840 m) and lowest sample (3369 m) lie within the root's bounds.
    EXPECT_LE(info.min_height, 3369.0);
    EXPECT_GE(info.max_height, 8840.0);
    EXPECT_TRUE(info.geographic);
    ASSERT_TRUE(info.geotransform.has_value());
    EXPECT_NEAR((*info.geotransform)[1], 1.0 / 1200.0, 1e-12);
    // Spacing in metres from the 3" geographic grid at 28° N.
    EXPECT_NEAR(info.spacing_y, 92.6, 0.5);
    EXPECT_NEAR(info.spacing_x, 81.8, 0.5);
}

TEST(PublicApi, ErrorsCrossTheLibraryBoundaryAndNameTheProblem)
{
    ScratchDir dir;
    try {
        const ridge::Terrain terrain(dir.path("missing.ridge"));
        FAIL() << "opened a missing archive";
    } catch (const ridge::Error& e) {
        EXPECT_NE(std::string(e.what()).find("missing.ridge"), std::string::npos) << e.what();
    }
    ridge::BuildParameters p;
    p.patch_size = 100; // not 2^n + 1
    try {
        ridge::build(dataPath("everest_crop.tif"), dir.path("a.ridge"), p);
        FAIL() << "built with patch_size 100";
    } catch (const ridge::Error& e) {
        EXPECT_NE(std::string(e.what()).find("100"), std::string::npos) << e.what();
        EXPECT_TRUE(std::string(e.what()).find("patch_size") != std::string::npos ||
                    std::string(e.what()).find("patch size") != std::string::npos)
            << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir.path("a.ridge")));
    // Never over the input.
    std::filesystem::copy_file(dataPath("everest_crop.tif"), dir.path("source.tif"));
    EXPECT_THROW(ridge::build(dir.path("source.tif"), dir.path("source.tif")), ridge::Error);
    EXPECT_EQ(std::filesystem::file_size(dir.path("source.tif")),
              std::filesystem::file_size(dataPath("everest_crop.tif")));
}

TEST(PublicApi, CancelledBuildLeavesNothing)
{
    ScratchDir dir;
    ridge::BuildParameters p;
    p.patch_size = 33;
    p.progress = [](double fraction) { return fraction < 0.3; };
    EXPECT_THROW(ridge::build(dataPath("everest_crop.tif"), dir.path("c.ridge"), p),
                 ridge::Cancelled);
    EXPECT_TRUE(ridge::test::namesIn(dir.dir()).empty());
}

TEST(PublicApi, VerifyHoldsTheBoundAndReportsCorruption)
{
    ScratchDir dir;
    const std::string path = everestArchive(dir, "progressive");
    const ridge::VerifySummary ok = ridge::verify(path, dataPath("everest_crop.tif"));
    EXPECT_TRUE(ok.ok);
    EXPECT_TRUE(ok.source_checked);
    EXPECT_GE(ok.samples_checked, 301 * 203);
    EXPECT_EQ(ok.bound_violations, 0);
    EXPECT_GT(ok.max_error, 0.0);

    // Flip one byte in the middle of the blobs: the CRC names the patch.
    {
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(400);
        char c = 0;
        f.read(&c, 1);
        c = char(c ^ 0x5a);
        f.seekp(400);
        f.write(&c, 1);
    }
    const ridge::VerifySummary bad = ridge::verify(path);
    EXPECT_FALSE(bad.ok);
    ASSERT_FALSE(bad.problems.empty());
    EXPECT_NE(bad.problems.front().find(path), std::string::npos) << bad.problems.front();
}

TEST(PublicApi, RendersAPngHeadless)
{
    ScratchDir dir;
    const std::string path = everestArchive(dir);
    ridge::RenderParameters p;
    p.width = 160;
    p.height = 90;
    p.samples = 1;
    const ridge::FrameSummary frame = ridge::renderPng(path, dir.path("e.png"), p);
    EXPECT_GE(frame.patches, 1);
    EXPECT_GT(frame.triangles, 0u);
    EXPECT_GT(std::filesystem::file_size(dir.path("e.png")), 1000u);

    p.width = 0;
    EXPECT_THROW(ridge::renderPng(path, dir.path("f.png"), p), ridge::Error);
    p.width = 160;
    p.draw.scheme = "no-such-scheme";
    EXPECT_THROW(ridge::renderPng(path, dir.path("f.png"), p), ridge::Error);
    p.draw.scheme = ridge::lodSchemes().front() + ",no-such-option=1";
    EXPECT_THROW(ridge::renderPng(path, dir.path("f.png"), p), ridge::Error);
    p.draw.scheme = ridge::lodSchemes().front();
    p.draw.max_screen_error_px = std::nan("");
    EXPECT_THROW(ridge::renderPng(path, dir.path("f.png"), p), ridge::Error);
    EXPECT_FALSE(std::filesystem::exists(dir.path("f.png")));
}

TEST(PublicApi, HeightsWithoutGl)
{
    ScratchDir dir;
    const std::string path = everestArchive(dir);
    const ridge::Terrain terrain(path);
    const ridge::TerrainInfo& info = terrain.info();
    const int finest = info.levels - 1;
    // A sample centre (pixel/line + 0.5) reads that sample; the finest level is the default.
    const ridge::LocalPoint p = terrain.localFromPixel(120.5, 80.5);
    EXPECT_DOUBLE_EQ(p.x, 120 * info.spacing_x);
    EXPECT_DOUBLE_EQ(p.y, (info.height - 1 - 80) * info.spacing_y);
    const std::optional<double> h = terrain.height(p.x, p.y);
    ASSERT_TRUE(h.has_value());
    EXPECT_EQ(*h, terrain.heightAtLevel(p.x, p.y, finest).value());
    EXPECT_GE(*h, info.min_height);
    EXPECT_LE(*h, info.max_height);
    // Between samples: inside the range of the four around it (bilinear).
    const ridge::LocalPoint q = terrain.localFromPixel(120.75, 80.25);
    const double hq = terrain.height(q.x, q.y).value();
    double lo = 1e9, hi = -1e9;
    for (double dx : {0.0, 1.0})
        for (double dy : {0.0, 1.0}) {
            const ridge::LocalPoint c = terrain.localFromPixel(120.5 + dx, 80.5 + dy);
            lo = std::min(lo, *terrain.height(c.x, c.y));
            hi = std::max(hi, *terrain.height(c.x, c.y));
        }
    EXPECT_GE(hq, lo);
    EXPECT_LE(hq, hi);
    // Coarser levels draw a different surface, within the root's bounds.
    const double h0 = terrain.heightAtLevel(p.x, p.y, 0).value();
    EXPECT_GE(h0, info.min_height);
    EXPECT_LE(h0, info.max_height);
    // Longitude/latitude round trip through PROJ, and the CRS (here lon/lat itself).
    const auto [lon, lat] = terrain.lonLatFromLocal(p.x, p.y);
    const auto& gt = *info.geotransform;
    EXPECT_NEAR(lon, gt[0] + 120.5 * gt[1], 1e-9);
    EXPECT_NEAR(lat, gt[3] + 80.5 * gt[5], 1e-9);
    const ridge::LocalPoint back = terrain.localFromLonLat(lon, lat);
    EXPECT_NEAR(back.x, p.x, 1e-6);
    EXPECT_NEAR(back.y, p.y, 1e-6);
    const ridge::LocalPoint crs = terrain.localFromCrs(lon, lat);
    EXPECT_NEAR(crs.x, p.x, 1e-6);
    // Off the terrain: no height; bad numbers and levels: errors naming them.
    EXPECT_FALSE(terrain.height(-1000.0, p.y).has_value());
    EXPECT_FALSE(terrain.height(p.x, 1e7).has_value());
    EXPECT_THROW(terrain.height(std::nan(""), 0.0), ridge::Error);
    EXPECT_THROW(terrain.heightAtLevel(p.x, p.y, info.levels), ridge::Error);
    EXPECT_THROW(terrain.heightAtLevel(p.x, p.y, -1), ridge::Error);
    EXPECT_THROW(terrain.localFromLonLat(0.0, 95.0), ridge::Error);
}

TEST(PublicApi, KeptNodataHasNoHeight)
{
    // The UTM-warped fixture's collar is border-connected nodata: kept by default.
    ScratchDir dir;
    const std::string path = dir.path("utm.ridge");
    ridge::BuildParameters p;
    p.patch_size = 33;
    const ridge::BuildSummary built = ridge::build(dataPath("everest_utm44.tif"), path, p);
    EXPECT_GT(built.voids_kept, 5000);
    EXPECT_EQ(built.voids_filled, 0);
    const ridge::Terrain terrain(path);
    const ridge::LocalPoint corner = terrain.localFromPixel(0.5, 0.5); // in the collar
    EXPECT_FALSE(terrain.height(corner.x, corner.y).has_value());
    const ridge::LocalPoint centre =
        terrain.localFromPixel(0.5 * terrain.info().width, 0.5 * terrain.info().height);
    EXPECT_TRUE(terrain.height(centre.x, centre.y).has_value());

    p.fill_voids = "all"; // the collar invented: every point has a height
    const std::string filled = dir.path("filled.ridge");
    EXPECT_EQ(ridge::build(dataPath("everest_utm44.tif"), filled, p).voids_kept, 0);
    EXPECT_TRUE(ridge::Terrain(filled).height(corner.x, corner.y).has_value());
    p.fill_voids = "some";
    EXPECT_THROW(ridge::build(dataPath("everest_utm44.tif"), dir.path("x.ridge"), p), ridge::Error);
}

} // namespace
