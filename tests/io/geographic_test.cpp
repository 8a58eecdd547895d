// io::GeographicTransform against GDAL's own coordinate transformation (OGR), round trips,
// and its refusals; formatDms against gdalinfo's text.
#include "test_support.h"

#include "ridge/core/error.h"
#include "ridge/io/geographic.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>

#include <cmath>

using namespace ridge;

namespace {

std::string wktOf(const std::string& path)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
    const std::string wkt = ds ? GDALGetProjectionRef(ds) : "";
    if (ds)
        GDALClose(ds);
    return wkt;
}

} // namespace

TEST(GeographicTransform, AgreesWithOgrAndRoundTripsOnUtm)
{
    const std::string wkt = wktOf(test::dataPath("everest_utm45.tif"));
    ASSERT_FALSE(wkt.empty());
    const io::GeographicTransform t(wkt, "everest_utm45.tif");
    EXPECT_FALSE(t.geographic());
    EXPECT_NE(t.crsName().find("UTM zone 45N"), std::string::npos) << t.crsName();

    OGRSpatialReferenceH wgs84 = OSRNewSpatialReference(nullptr);
    OSRImportFromEPSG(wgs84, 4326);
    OSRSetAxisMappingStrategy(wgs84, OAMS_TRADITIONAL_GIS_ORDER);
    OGRSpatialReferenceH utm = OSRNewSpatialReference(wkt.c_str());
    OSRSetAxisMappingStrategy(utm, OAMS_TRADITIONAL_GIS_ORDER);
    OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(wgs84, utm);
    ASSERT_NE(ct, nullptr);
    double worst_m = 0.0, worst_deg = 0.0;
    for (double lon = 84.0; lon <= 90.0; lon += 0.75)
        for (double lat = 0.0; lat <= 60.0; lat += 7.5) {
            double x = lon, y = lat;
            ASSERT_TRUE(OCTTransform(ct, 1, &x, &y, nullptr));
            const auto p = t.fromLonLat(lon, lat);
            EXPECT_NEAR(p[0], x, 1e-6) << lon << "," << lat;
            EXPECT_NEAR(p[1], y, 1e-6) << lon << "," << lat;
            const auto ll = t.toLonLat(p[0], p[1]);
            worst_deg = std::max({worst_deg, std::abs(ll[0] - lon), std::abs(ll[1] - lat)});
            const auto again = t.fromLonLat(ll[0], ll[1]);
            worst_m = std::max({worst_m, std::abs(again[0] - p[0]), std::abs(again[1] - p[1])});
        }
    OCTDestroyCoordinateTransformation(ct);
    OSRDestroySpatialReference(utm);
    OSRDestroySpatialReference(wgs84);
    EXPECT_LT(worst_deg, 1e-9);
    EXPECT_LT(worst_m, 1e-6);
}

TEST(GeographicTransform, GeographicCrsIsLonLatFirst)
{
    // EPSG:4326's definition says latitude first; ridge works east first, as geotransforms do.
    const io::GeographicTransform t(wktOf(test::dataPath("everest_crop.tif")), "everest_crop.tif");
    EXPECT_TRUE(t.geographic());
    const auto p = t.fromLonLat(86.925, 27.988);
    EXPECT_NEAR(p[0], 86.925, 1e-12);
    EXPECT_NEAR(p[1], 27.988, 1e-12);
    const auto ll = t.toLonLat(86.925, 27.988);
    EXPECT_NEAR(ll[0], 86.925, 1e-12);
    EXPECT_NEAR(ll[1], 27.988, 1e-12);
}

TEST(GeographicTransform, RefusesWhatItCannotConvert)
{
    try {
        io::GeographicTransform("", "a.ridge");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("a.ridge: has no CRS"), std::string::npos) << e.what();
    }
    EXPECT_THROW(io::GeographicTransform("not a crs", "a.ridge"), Error);
    const io::GeographicTransform t(wktOf(test::dataPath("everest_utm45.tif")), "u");
    for (auto [lon, lat] : {std::pair{double(NAN), 10.0}, std::pair{10.0, double(INFINITY)},
                            std::pair{10.0, 90.5}, std::pair{361.0, 0.0}, std::pair{0.0, -91.0}}) {
        try {
            t.fromLonLat(lon, lat);
            FAIL() << lon << "," << lat;
        } catch (const Error& e) {
            const std::string m = e.what();
            EXPECT_TRUE(m.find("longitude") != std::string::npos ||
                        m.find("latitude") != std::string::npos)
                << m;
        }
    }
    EXPECT_THROW(t.toLonLat(NAN, 0), Error);
}

TEST(GeographicTransform, DmsIsGdalinfos)
{
    // gdalinfo everest_crop.tif: Upper Left ( 86d44'58.50"E, 28d 0' 1.50"N)
    EXPECT_EQ(io::formatDms(86.7495833333, true), " 86d44'58.50\"E");
    EXPECT_EQ(io::formatDms(28.0004166667, false), " 28d 0' 1.50\"N");
    EXPECT_EQ(io::formatDms(-121.5, true), "121d30' 0.00\"W");
    EXPECT_EQ(io::formatDms(-0.25, false), "  0d15' 0.00\"S");
}
