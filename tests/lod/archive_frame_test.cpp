// Which frame an archive is drawn in (lod/archive_frame.h): the whole-globe fixture goes on the
// ellipsoid by itself, wrapping at 360° with both poles; a small geographic tile only when
// asked; a UTM raster, when asked, where PROJ puts its samples; and every archive that cannot
// lie on the ellipsoid is refused with a message that names it and says why — never a frame
// with NaNs in it.
#include "error_expectations.h"
#include "gdal_translate.h"
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/io/geographic.h"
#include "ridge/io/raster_source.h"
#include "ridge/lod/archive_frame.h"
#include "ridge/pipeline/build.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>

namespace ridge::lod {
namespace {

class ArchiveFrame : public ::testing::Test {
  protected:
    static void SetUpTestSuite() { scratch_ = new test::ScratchDir(); }
    static void TearDownTestSuite() { delete scratch_; }

    // `tif` (in tests/data, or made in the scratch directory) built losslessly.
    static std::string build(const std::string& tif, const std::string& name)
    {
        const std::string out = scratch_->path(name + ".ridge");
        BuildOptions options;
        options.patch_size = 17;
        options.progress = {};
        buildArchive(tif, out, options);
        return out;
    }
    // everest_crop.tif with its corners moved to (west, north) .. (east, south), degrees.
    static std::string moved(const std::string& name, std::vector<std::string> ullr)
    {
        const std::string tif = scratch_->path(name + ".tif");
        ullr.insert(ullr.begin(), "-a_ullr");
        test::gdalTranslate(test::dataPath("everest_crop.tif"), tif, ullr);
        return build(tif, name);
    }

    static test::ScratchDir* scratch_;
};

test::ScratchDir* ArchiveFrame::scratch_ = nullptr;

TEST_F(ArchiveFrame, TheWholeGlobeGoesOnTheEllipsoidWrappingWithBothPoles)
{
    const archive::ArchiveReader reader(build(test::dataPath("etopo5_globe_181x91.tif"), "globe"));
    const TerrainFrame f = terrainFrameOf(reader, FrameChoice::Auto, reader.path());
    ASSERT_TRUE(f.onEllipsoid());
    EXPECT_EQ(f.geodetic().wrap_columns, 180);
    EXPECT_DOUBLE_EQ(f.geodetic().dlon, 2.0 * std::numbers::pi / 180.0);
    EXPECT_TRUE(f.poleRow(0.0));
    EXPECT_TRUE(f.poleRow(90.0));
    // Column 180 repeats column 0 one turn on: the same points.
    EXPECT_LT(glm::length(f.worldOf(180.0, 40.0, 0.0) - f.worldOf(0.0, 40.0, 0.0)), 1e-6);
    // The plane when asked.
    EXPECT_FALSE(terrainFrameOf(reader, FrameChoice::Plane, reader.path()).onEllipsoid());
}

TEST_F(ArchiveFrame, ASmallGeographicTileStaysOnItsPlaneUnlessAsked)
{
    const archive::ArchiveReader reader(build(test::dataPath("everest_crop.tif"), "everest"));
    EXPECT_FALSE(terrainFrameOf(reader, FrameChoice::Auto, reader.path()).onEllipsoid());
    const TerrainFrame f = terrainFrameOf(reader, FrameChoice::Ellipsoid, reader.path());
    ASSERT_TRUE(f.onEllipsoid());
    EXPECT_EQ(f.geodetic().wrap_columns, 0);
    // Sample (0, 0) is GDAL pixel (0, 0)'s centre: 86.75°E, 28.0°N (3″ pixels).
    EXPECT_NEAR(f.longitudeOf(0.0) * 180.0 / std::numbers::pi, 86.749583333 + 0.5 / 1200.0, 1e-9);
    EXPECT_NEAR(f.latitudeOf(0.0) * 180.0 / std::numbers::pi, 28.000416667 - 0.5 / 1200.0, 1e-9);
    // Plane spacings keep their meaning: ground metres of a sample step at the centre.
    EXPECT_DOUBLE_EQ(f.spacingX(), reader.header().spacing_x); // 82.03 m
    EXPECT_DOUBLE_EQ(f.spacingY(), reader.header().spacing_y); // 92.35 m
}

// The finest sample with the largest height of a raster: (column, row).
glm::dvec2 highestSample(const std::string& tif)
{
    const io::ElevationRaster r = io::ingestRaster(tif);
    glm::dvec2 best(0.0);
    for (int y = 0; y < r.grid.height; ++y)
        for (int x = 0; x < r.grid.width; ++x)
            if (r.grid.at(x, y) > r.grid.at(int(best.x), int(best.y)))
                best = {x, y};
    return best;
}

TEST_F(ArchiveFrame, AUtmRasterLiesOnTheEllipsoidWherePROJPutsItsSamples)
{
    const archive::ArchiveReader reader(build(test::dataPath("everest_utm45.tif"), "utm"));
    // auto keeps a regional raster on its plane; the ellipsoid when asked.
    EXPECT_FALSE(terrainFrameOf(reader, FrameChoice::Auto, reader.path()).onEllipsoid());
    const TerrainFrame f = terrainFrameOf(reader, FrameChoice::Ellipsoid, reader.path());
    ASSERT_TRUE(f.onEllipsoid());
    ASSERT_NE(f.projectedGrid(), nullptr);
    EXPECT_LE(f.projectedGrid()->measuredError(), 1e-3);
    EXPECT_EQ(f.geodetic().wrap_columns, 0);
    EXPECT_FALSE(f.poleRow(0.0));

    // Against PROJ itself, sample by sample (fractions too), at heights from the sea floor to
    // orbit: the lattice's surface is the projection to the millimetre.
    const archive::GeoreferenceMetadata& geo = reader.metadata().georeference;
    const std::array<double, 6>& gt = *geo.geotransform;
    const io::GeographicTransform proj(geo.crs_wkt, "utm");
    const Ellipsoid e = Ellipsoid::wgs84();
    std::mt19937 rng(26);
    std::uniform_real_distribution<double> col(0.0, f.geometry().width() - 1.0);
    std::uniform_real_distribution<double> row(0.0, f.geometry().height() - 1.0);
    double worst = 0.0, worst_inverse = 0.0;
    for (int k = 0; k < 400; ++k) {
        const double c = k < 4 ? (k & 1) * (f.geometry().width() - 1.0) : col(rng);
        const double r = k < 4 ? (k >> 1) * (f.geometry().height() - 1.0) : row(rng);
        const double h = std::array<double, 4>{-400.0, 0.0, 8848.0, 4e5}[size_t(k % 4)];
        const std::array<double, 2> ll =
            proj.toLonLat(gt[0] + (c + 0.5) * gt[1], gt[3] + (r + 0.5) * gt[5]);
        const glm::dvec3 exact = geodeticToEcef(e, ll[0] * std::numbers::pi / 180.0,
                                                ll[1] * std::numbers::pi / 180.0, h);
        worst = std::max(worst, glm::length(f.worldOf(c, r, h) - exact));
        const glm::dvec3 g = f.gridOf(exact);
        worst_inverse = std::max({worst_inverse, std::abs(g.x - c), std::abs(g.y - r)});
        EXPECT_NEAR(g.z, h, 1e-3);
        // The local up is the ellipsoid's normal there.
        const glm::dvec3 up =
            geodeticUp(ll[0] * std::numbers::pi / 180.0, ll[1] * std::numbers::pi / 180.0);
        EXPECT_GT(glm::dot(f.upAt(c, r), up), 1.0 - 1e-12);
    }
    EXPECT_LT(worst, 2e-3) << "metres from PROJ's point";
    EXPECT_LT(worst_inverse, 1e-4) << "samples";

    // The same mountain as the geographic tile it was warped from, in the same place: their
    // highest samples within two 90 m samples of each other.
    const archive::ArchiveReader geographic(build(test::dataPath("everest_crop.tif"), "geo"));
    const TerrainFrame fg = terrainFrameOf(geographic, FrameChoice::Ellipsoid, geographic.path());
    const glm::dvec2 a = highestSample(test::dataPath("everest_utm45.tif"));
    const glm::dvec2 b = highestSample(test::dataPath("everest_crop.tif"));
    EXPECT_LT(glm::length(f.worldOf(a.x, a.y, 0.0) - fg.worldOf(b.x, b.y, 0.0)), 180.0);

    // Bounds that hold: the ground metres of a column or a row, and the chord's sagitta of
    // the whole raster's width is that of ~24 km on the Earth (~11 m).
    EXPECT_GE(f.columnAngle() * e.b(), 89.9);
    EXPECT_LE(f.columnAngle() * e.b(), 92.0);
    const double sag = f.chordSag(double(f.geometry().width() - 1));
    EXPECT_GT(sag, 10.0);
    EXPECT_LT(sag, 30.0);
}

TEST_F(ArchiveFrame, WhatCannotLieOnTheEllipsoidIsRefusedByName)
{
    auto refused = [](const std::string& path, const std::string& phrase) {
        const archive::ArchiveReader reader(path);
        test::expectError([&] { terrainFrameOf(reader, FrameChoice::Ellipsoid, path); }, phrase);
        test::expectError([&] { terrainFrameOf(reader, FrameChoice::Ellipsoid, path); }, path);
        // auto falls back to the plane, the frame such an archive has always had.
        EXPECT_FALSE(terrainFrameOf(reader, FrameChoice::Auto, path).onEllipsoid());
    };
    refused(moved("beyond_pole", {"86.75", "95.0", "87.0", "94.83"}), "beyond the pole");
    refused(moved("too_wide", {"0", "28", "400", "27.83"}), "more than the 360°");
    refused(moved("south_up", {"86.75", "27.83", "87.0", "28.0"}), "north-up");

    // A geotransform without a CRS: an ASCII grid whose .prj is gone.
    const std::string no_crs = scratch_->path("no_crs.asc");
    test::gdalTranslate(test::dataPath("everest_crop.tif"), no_crs, {"-of", "AAIGrid"});
    std::filesystem::remove(scratch_->path("no_crs.prj"));
    std::filesystem::remove(no_crs + ".aux.xml");
    refused(build(no_crs, "no_crs"), "no CRS");
}

TEST(FrameChoiceNames, RoundTrip)
{
    for (FrameChoice c : {FrameChoice::Auto, FrameChoice::Plane, FrameChoice::Ellipsoid})
        EXPECT_EQ(parseFrameChoice(frameChoiceName(c)), c);
    EXPECT_FALSE(parseFrameChoice("globe").has_value());
}

} // namespace
} // namespace ridge::lod
