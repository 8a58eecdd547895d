// The source band (IngestOptions::band, gdal_translate's -b) and the heights' vertical datum
// (io/crs_summary.h), on rasters made from the real fixtures with GDAL.
#include "ridge/core/error.h"
#include "ridge/io/crs_summary.h"
#include "ridge/io/raster_source.h"

#include "gdal_translate.h"
#include "test_support.h"

#include <gdal.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

using namespace ridge;

namespace {

using test::gdalTranslate;

std::string errorOf(const std::function<void()>& f)
{
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

} // namespace

// Three bands of the Everest heights, each a different stretch: reading band B gives band B's
// values, the probe names every band, and a band the file lacks is refused naming both numbers.
TEST(SourceBand, ReadsTheBandAskedForAndNamesEveryBand)
{
    test::ScratchDir dir;
    const std::string tif = dir.path("three.tif");
    gdalTranslate(test::dataPath("everest_crop.tif"), tif,
                  {"-b",           "1",
                   "-b",           "1",
                   "-b",           "1",
                   "-a_nodata",    "none",
                   "-scale_2",     "3369",
                   "8840",         "0",
                   "1000",         "-scale_3",
                   "3369",         "8840",
                   "8840",         "3369",
                   "-ot",          "Int16",
                   "-colorinterp", "gray,undefined,undefined"});
    const io::RasterProbe probe = io::probeRaster(tif);
    // Colour interpretation where GDAL has one, else the band's number.
    EXPECT_EQ(probe.band_names, (std::vector<std::string>{"Gray", "band 2", "band 3"}));

    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(tif.c_str(), GA_ReadOnly);
    ASSERT_NE(ds, nullptr);
    for (int b = 1; b <= 3; ++b) {
        SCOPED_TRACE(b);
        std::vector<double> expected(301 * 203);
        ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(ds, b), GF_Read, 0, 0, 301, 203, expected.data(),
                               301, 203, GDT_Float64, 0, 0),
                  CE_None);
        io::IngestOptions options;
        options.band = b;
        const io::ElevationRaster r = io::ingestRaster(tif, options);
        ASSERT_EQ(r.grid.codes.size(), expected.size());
        size_t equal = 0;
        for (size_t i = 0; i < expected.size(); ++i)
            equal += r.quantization.toMetres(r.grid.codes[i]) == expected[i];
        EXPECT_EQ(equal, expected.size()) << "every sample is band " << b << "'s";
        // The streaming reader takes the same band.
        io::CodeRowReader rows(tif, options);
        std::vector<uint16_t> codes(size_t(301) * 203);
        rows.readRows(0, 203, codes.data());
        EXPECT_EQ(codes, r.grid.codes);
    }
    GDALClose(ds);

    io::IngestOptions options;
    options.band = 4;
    std::string message = errorOf([&] { io::ingestRaster(tif, options); });
    EXPECT_NE(message.find(tif + ": band 4 was asked for, but it has 3 bands (1..3)"),
              std::string::npos)
        << message;
    options.band = 0;
    message = errorOf([&] { io::ingestRaster(tif, options); });
    EXPECT_NE(message.find("band is 0"), std::string::npos) << message;
}

// The vertical datum from a compound CRS, from an EPSG code or name given by the user (which
// wins over the CRS), and refusals for codes that are no vertical CRS.
TEST(VerticalDatum, FromTheCompoundCrsOrTheUser)
{
    test::ScratchDir dir;
    const std::string compound = dir.path("compound.tif");
    gdalTranslate(test::dataPath("everest_crop.tif"), compound, {"-a_srs", "EPSG:4326+5773"});
    io::IngestOptions options;
    options.vertical_shift = io::VerticalShift::None; // the datum as stated, heights kept
    io::ElevationRaster r = io::ingestRaster(compound, options);
    EXPECT_EQ(r.geo.vertical_datum.name, "EGM96 height");
    EXPECT_EQ(r.geo.vertical_datum.epsg, 5773);
    EXPECT_EQ(r.geo.vertical_datum.origin, "source CRS");
    EXPECT_EQ(r.geo.vertical_datum.describe(), "EGM96 height (EPSG:5773)");

    options.vertical_datum = "EPSG:3855";
    r = io::ingestRaster(compound, options);
    EXPECT_EQ(r.geo.vertical_datum.name, "EGM2008 height");
    EXPECT_EQ(r.geo.vertical_datum.origin, "--vertical-datum");

    // A horizontal CRS alone states no datum.
    r = io::ingestRaster(test::dataPath("everest_crop.tif"));
    EXPECT_FALSE(r.geo.vertical_datum.known());

    const io::CrsSummary utm = io::summarizeCrs(r.geo.crs_wkt, "x");
    EXPECT_EQ(utm.name, "WGS 84");
    EXPECT_EQ(utm.epsg, 4326);

    EXPECT_EQ(io::resolveVerticalDatum("5773").name, "EGM96 height");
    EXPECT_EQ(io::resolveVerticalDatum(" epsg:5773 ").epsg, 5773);
    EXPECT_EQ(io::resolveVerticalDatum("NAVD88 height").epsg, 5703);
    const io::VerticalDatum local = io::resolveVerticalDatum("Khumbu survey datum");
    EXPECT_EQ(local.name, "Khumbu survey datum");
    EXPECT_FALSE(local.epsg.has_value());

    for (const auto& [text, phrase] : std::vector<std::pair<std::string, std::string>>{
             {"EPSG:4326", "is a geographic CRS, not a vertical one"},
             {"EPSG:32645", "is a projected CRS, not a vertical one"},
             {"999999", "PROJ's database has no EPSG CRS 999999"},
             {"", "empty"},
             {"   ", "empty"},
             {std::string("a\tb\x01"), "control character"},
             {std::string(200, 'x'), "at most 120"}}) {
        const std::string message = errorOf([&, &t = text] { io::resolveVerticalDatum(t); });
        EXPECT_NE(message.find("vertical_datum"), std::string::npos) << message;
        EXPECT_NE(message.find(phrase), std::string::npos) << text << ": " << message;
    }
    // Refused with the options, before a sample is read.
    options.vertical_datum = "EPSG:4326";
    EXPECT_NE(errorOf([&] { io::probeRaster(compound, options); }).find("not a vertical one"),
              std::string::npos);
}
