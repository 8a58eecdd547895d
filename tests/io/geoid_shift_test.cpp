// Heights above EGM96 shifted to the WGS 84 ellipsoid through PROJ and its real grid
// (proj-data's egm96_15.gtx): the undulation against NGA's published test values, the
// default (only where the datum is known), water judged before the shift, the globe's wrap
// column, and the refusals that name the missing datum or grid.
#include "ridge/core/error.h"
#include "ridge/core/sample_flag_bits.h"
#include "ridge/io/raster_source.h"

#include "error_expectations.h"
#include "io_test_support.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace ridge;

namespace {

// A 2x2 Float32 geographic raster of `heights` whose sample (0, 0) is centred on (lon, lat).
std::string rasterAt(const test::ScratchDir& dir, const std::string& name, double lon, double lat,
                     double height)
{
    const double d = 1e-4; // degrees: N does not change across it
    test::RasterSetup setup;
    setup.epsg = 4326;
    setup.geotransform = std::array<double, 6>{lon - d / 2, d, 0, lat + d / 2, 0, -d};
    const std::string path = dir.path(name);
    test::writeTestRaster(path, "GTiff", GDT_Float32, 2, 2, std::vector<double>(4, height), setup);
    return path;
}

// "p3.tif" (appended: GCC 12's -Wrestrict misfires on a literal + std::string temporary).
std::string numbered(const char* stem, int k)
{
    return std::string(stem).append(std::to_string(k)).append(".tif");
}

double firstSampleMetres(const std::string& path, const io::IngestOptions& options)
{
    io::ReferenceRaster raster(path, options);
    std::vector<double> row(2 * 2);
    raster.readRows(0, 2, row.data());
    return row[0];
}

} // namespace

// NGA's EGM96 test points (the readme of its interpolation program, 15' grid): N to the
// centimetre from the spherical harmonics; PROJ interpolates the 15' grid bilinearly, which
// stays within 6 cm of them.
TEST(GeoidShift, UndulationMatchesNgaTestValues)
{
    struct Point {
        double lat, lon, n;
    };
    const Point points[] = {{38.6281550, 269.7791550, -31.628}, {-14.6212170, 305.0211140, -2.969},
                            {46.8743190, 102.4487290, -43.575}, {-23.6174460, 133.8747120, 15.871},
                            {38.6254730, 359.9995000, 50.066},  {-0.4667440, 0.0023000, 17.329}};
    test::ScratchDir dir;
    io::IngestOptions options;
    options.vertical_datum = "EPSG:5773";
    int k = 0;
    for (const Point& p : points) {
        const double lon = p.lon > 180 ? p.lon - 360 : p.lon;
        const std::string path = rasterAt(dir, numbered("p", k++), lon, p.lat, 0.0);
        EXPECT_NEAR(firstSampleMetres(path, options), p.n, 0.1) << p.lat << ", " << p.lon;
        // A height above the geoid keeps its own part: h = H + N.
        const std::string high = rasterAt(dir, numbered("h", k), lon, p.lat, 1000);
        EXPECT_NEAR(firstSampleMetres(high, options), 1000 + p.n, 0.1);
    }
}

// Auto shifts only where the heights' datum is a registered vertical CRS; --novshift keeps
// them; the georeference says which happened.
TEST(GeoidShift, DefaultFollowsTheDatum)
{
    test::ScratchDir dir;
    const std::string path = rasterAt(dir, "equator.tif", 0.0023, -0.466744, 100.0);
    io::IngestOptions options;
    EXPECT_DOUBLE_EQ(firstSampleMetres(path, options), 100.0) << "no datum stated: kept";
    io::ElevationRaster r = io::ingestRaster(path, options);
    EXPECT_FALSE(r.geo.vertical_shift.has_value());

    options.vertical_datum = "EPSG:5773";
    r = io::ingestRaster(path, options);
    ASSERT_TRUE(r.geo.vertical_shift.has_value());
    EXPECT_EQ(r.geo.vertical_shift->from.epsg, 5773);
    EXPECT_NE(r.geo.vertical_shift->operation.find("EGM96"), std::string::npos)
        << r.geo.vertical_shift->operation;
    EXPECT_EQ(r.geo.vertical_datum.name, "WGS 84 ellipsoidal height");
    EXPECT_FALSE(r.quantization.max_error > 0.01) << "a Float32 source quantizes finely";
    EXPECT_NEAR(r.quantization.toMetres(r.grid.codes[0]), 117.3, 0.1);

    options.vertical_shift = io::VerticalShift::None;
    EXPECT_DOUBLE_EQ(firstSampleMetres(path, options), 100.0);
    r = io::ingestRaster(path, options);
    EXPECT_FALSE(r.geo.vertical_shift.has_value());
    EXPECT_EQ(r.geo.vertical_datum.name, "EGM96 height");
}

// Sea level is a geoid height: a 0 m sea is water though it sits 17 m above the ellipsoid.
TEST(GeoidShift, WaterIsJudgedBeforeTheShift)
{
    test::ScratchDir dir;
    const std::string path = rasterAt(dir, "sea.tif", 0.0023, -0.466744, 0.0);
    io::IngestOptions options;
    options.vertical_datum = "EPSG:5773";
    const io::ElevationRaster r = io::ingestRaster(path, options);
    EXPECT_NEAR(r.quantization.toMetres(r.grid.codes[0]), 17.3, 0.1);
    ASSERT_EQ(r.flags.size(), 4u);
    for (uint8_t f : r.flags)
        EXPECT_TRUE(f & kSampleWater);
    EXPECT_EQ(r.stats.water_samples, 4);
}

// The globe fixture's repeated column gets the same N as column 0, so the antimeridian seam
// stays closed after the shift.
TEST(GeoidShift, TheGlobesWrapColumnStaysClosed)
{
    io::IngestOptions options;
    options.vertical_datum = "EPSG:5773";
    const io::ElevationRaster r =
        io::ingestRaster(test::dataPath("etopo5_globe_181x91.tif"), options);
    ASSERT_TRUE(r.geo.vertical_shift.has_value());
    const int w = r.grid.width;
    for (int y = 0; y < r.grid.height; ++y)
        ASSERT_EQ(r.grid.codes[size_t(y) * w], r.grid.codes[size_t(y) * w + w - 1]) << "row " << y;
    options.vertical_shift = io::VerticalShift::None;
    const io::ElevationRaster kept =
        io::ingestRaster(test::dataPath("etopo5_globe_181x91.tif"), options);
    // Somewhere the two differ by tens of metres (N spans about −106..+85 m).
    double largest = 0;
    for (size_t i = 0; i < r.grid.codes.size(); i += 7)
        largest = std::max(largest, std::abs(r.quantization.toMetres(r.grid.codes[i]) -
                                             kept.quantization.toMetres(kept.grid.codes[i])));
    EXPECT_GT(largest, 50.0);
    EXPECT_LT(largest, 120.0);
}

TEST(GeoidShift, RefusalsNameTheDatumOrTheGrid)
{
    test::ScratchDir dir;
    const std::string path = rasterAt(dir, "x.tif", 10, 10, 5.0);
    io::IngestOptions options;
    options.vertical_shift = io::VerticalShift::Ellipsoid;
    test::expectPhrases(test::errorOf([&] { io::ingestRaster(path, options); }),
                        {path, "unknown datum", "--vertical-datum EPSG:5773", "--novshift"});
    options.vertical_datum = "Khumbu survey datum"; // known by name only: no transformation
    test::expectPhrases(test::errorOf([&] { io::ingestRaster(path, options); }),
                        {path, "Khumbu survey datum", "EPSG code"});
    // EGM2008's grid is not in Debian's proj-data: a clear refusal, not PROJ's ballpark N = 0.
    options.vertical_datum = "EPSG:3855";
    options.vertical_shift = io::VerticalShift::Auto;
    test::expectPhrases(
        test::errorOf([&] { io::ingestRaster(path, options); }),
        {path, "EGM2008 height (EPSG:3855)", "us_nga_egm08_25.tif", "not installed", "--novshift"});
    options.vertical_shift = io::VerticalShift::None;
    EXPECT_DOUBLE_EQ(firstSampleMetres(path, options), 5.0);
}
