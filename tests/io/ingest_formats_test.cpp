// ingestRaster on rasters the tests make at run time: PNG heightmaps, floating point,
// vertical units, masks, projected CRSs.
#include "io_test_support.h"
#include "test_support.h"

#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace ridge::io {
namespace {

using test::GdalBand;
using test::RasterSetup;
using test::readWithGdal;
using test::ScratchDir;
using test::writeTestRaster;

// The real Everest crop, as the values every synthetic-format test starts from.
GdalBand everest()
{
    return readWithGdal(test::dataPath("everest_crop.tif"));
}

// Largest |toMetres(code) - metres| over valid samples, computed independently.
double bruteForceError(const ElevationRaster& r, const GdalBand& source, double z_scale = 1.0)
{
    double worst = 0;
    for (size_t i = 0; i < source.values.size(); ++i)
        if (!source.isNodata(i))
            worst = std::max(worst, std::abs(r.quantization.toMetres(r.grid.codes[i]) -
                                             source.values[i] * z_scale));
    return worst;
}

TEST(Ingest, ReadsA16BitPngHeightmapWithUserSpacingAndZScale)
{
    ScratchDir dir;
    const int w = 37, h = 29;
    std::vector<double> values(w * h);
    for (int i = 0; i < w * h; ++i)
        values[i] = (i * 2654435761u) % 65536; // covers the whole 16-bit range
    values[0] = 0;
    values[1] = 65535;
    const std::string path = dir.path("height.png");
    writeTestRaster(path, "PNG", GDT_UInt16, w, h, values);

    const ElevationRaster plain = ingestRaster(path);
    EXPECT_EQ(plain.stats.data_type, "UInt16");
    EXPECT_TRUE(plain.geo.spacing_from_user);
    EXPECT_FALSE(plain.geo.has_geotransform);
    EXPECT_TRUE(plain.geo.crs_wkt.empty());
    EXPECT_EQ(plain.geo.spacing_x, 1.0);
    EXPECT_EQ(plain.geo.spacing_y, 1.0);

    IngestOptions options;
    options.z_scale = 0.1;
    options.spacing = 2.5;
    const ElevationRaster r = ingestRaster(path, options);
    EXPECT_TRUE(r.stats.exact);
    EXPECT_EQ(r.stats.z_scale, 0.1);
    EXPECT_EQ(r.quantization.scale, 0.1);
    EXPECT_EQ(r.geo.spacing_x, 2.5);
    EXPECT_EQ(r.geo.spacing_y, 2.5);
    EXPECT_NEAR(r.stats.max_metres, 6553.5, 1e-9);
    for (int i = 0; i < w * h; ++i) {
        ASSERT_EQ(r.grid.codes[i], values[i]);
        ASSERT_NEAR(r.quantization.toMetres(r.grid.codes[i]), values[i] * 0.1, 1e-9);
    }
    // A leftover .aux.xml would mean GDAL wrote next to the input.
    EXPECT_FALSE(std::filesystem::exists(path + ".aux.xml"));
}

TEST(Ingest, ReadsAn8BitPngHeightmap)
{
    ScratchDir dir;
    const GdalBand src = everest();
    std::vector<double> values(src.values.size());
    for (size_t i = 0; i < values.size(); ++i)
        values[i] = std::round((src.values[i] - 3369) / (8840 - 3369) * 255);
    const std::string path = dir.path("height8.png");
    writeTestRaster(path, "PNG", GDT_Byte, src.width, src.height, values);

    const ElevationRaster r = ingestRaster(path);
    EXPECT_EQ(r.stats.data_type, "Byte");
    EXPECT_TRUE(r.stats.exact);
    EXPECT_TRUE(r.geo.spacing_from_user);
    EXPECT_EQ(r.stats.min_metres, 0.0);
    EXPECT_EQ(r.stats.max_metres, 255.0);
    for (size_t i = 0; i < values.size(); ++i)
        ASSERT_EQ(r.quantization.toMetres(r.grid.codes[i]), values[i]);
}

TEST(Ingest, ReadsSignedBytesExactly)
{
    ScratchDir dir;
    std::vector<double> values(32 * 8);
    for (size_t i = 0; i < values.size(); ++i)
        values[i] = double(int(i % 256) - 128);
    const std::string path = dir.path("signed.tif");
    RasterSetup setup;
    setup.creation_options = {"PIXELTYPE=SIGNEDBYTE"};
    // A MEM Byte band cannot hold negatives; write the two's complement bytes.
    std::vector<double> bytes(values.size());
    for (size_t i = 0; i < values.size(); ++i)
        bytes[i] = double(uint8_t(int8_t(values[i])));
    writeTestRaster(path, "GTiff", GDT_Byte, 32, 8, bytes, setup);

    const ElevationRaster r = ingestRaster(path);
    EXPECT_EQ(r.stats.data_type, "Int8");
    EXPECT_EQ(r.stats.min_metres, -128.0);
    EXPECT_EQ(r.stats.max_metres, 127.0);
    for (size_t i = 0; i < values.size(); ++i)
        ASSERT_EQ(r.quantization.toMetres(r.grid.codes[i]), values[i]);
}

TEST(Ingest, QuantizesFractionalFloatsWithinMaxError)
{
    ScratchDir dir;
    const GdalBand src = everest();
    std::vector<double> values(src.values.size());
    for (size_t i = 0; i < values.size(); ++i)
        values[i] = double(float(src.values[i] / 3.7 + 0.013 * (i % 7)));
    const std::string path = dir.path("fractional.tif");
    RasterSetup setup;
    setup.geotransform = src.geotransform;
    setup.epsg = 4326;
    writeTestRaster(path, "GTiff", GDT_Float32, src.width, src.height, values, setup);
    const GdalBand stored = readWithGdal(path);

    IngestOptions options;
    options.max_error = 0.05;
    const ElevationRaster r = ingestRaster(path, options);
    EXPECT_EQ(r.stats.data_type, "Float32");
    EXPECT_FALSE(r.stats.exact);
    EXPECT_LE(r.quantization.max_error, 0.05);
    EXPECT_GT(r.quantization.max_error, 0.04); // a 0.1 m step on ~60000 values does err
    EXPECT_NEAR(r.quantization.scale, 0.1, 1e-9);
    EXPECT_DOUBLE_EQ(r.quantization.max_error, bruteForceError(r, stored));
    EXPECT_EQ(r.stats.min_metres, *std::min_element(stored.values.begin(), stored.values.end()));
    EXPECT_EQ(r.stats.max_metres, *std::max_element(stored.values.begin(), stored.values.end()));

    // Without max_error: the finest step that fits 16 bits.
    const ElevationRaster fine = ingestRaster(path);
    const double range = fine.stats.max_metres - fine.stats.min_metres;
    EXPECT_NEAR(fine.quantization.scale, range / 65535, 1e-12);
    EXPECT_LE(fine.quantization.max_error, fine.quantization.scale / 2 * (1 + 1e-9));
    EXPECT_DOUBLE_EQ(fine.quantization.max_error, bruteForceError(fine, stored));
}

TEST(Ingest, IntegralFloatsAreExact)
{
    ScratchDir dir;
    const GdalBand src = everest();
    const std::string path = dir.path("integral.tif");
    writeTestRaster(path, "GTiff", GDT_Float32, src.width, src.height, src.values);
    IngestOptions options;
    options.max_error = 0.5; // exactness wins when it is possible
    const ElevationRaster r = ingestRaster(path, options);
    EXPECT_TRUE(r.stats.exact);
    EXPECT_EQ(r.quantization.max_error, 0.0);
    EXPECT_EQ(r.quantization.scale, 1.0);
    for (size_t i = 0; i < src.values.size(); ++i)
        ASSERT_EQ(r.quantization.toMetres(r.grid.codes[i]), src.values[i]);
}

TEST(Ingest, QuantizesWideIntegerRangesInMetres)
{
    // Millimetres in Int32 with the band scale saying so: 5.5 million distinct values.
    ScratchDir dir;
    const GdalBand src = everest();
    std::vector<double> mm(src.values.size());
    for (size_t i = 0; i < mm.size(); ++i)
        mm[i] = src.values[i] * 1000 + double(i % 997);
    const std::string path = dir.path("millimetres.tif");
    RasterSetup setup;
    setup.scale = 0.001;
    writeTestRaster(path, "GTiff", GDT_Int32, src.width, src.height, mm, setup);
    const ElevationRaster r = ingestRaster(path);
    EXPECT_EQ(r.stats.data_type, "Int32");
    EXPECT_FALSE(r.stats.exact);
    const double range = r.stats.max_metres - r.stats.min_metres;
    EXPECT_NEAR(r.quantization.scale, range / 65535, 1e-12);
    EXPECT_LE(r.quantization.max_error, r.quantization.scale / 2 * (1 + 1e-9));
    EXPECT_DOUBLE_EQ(r.quantization.max_error, bruteForceError(r, readWithGdal(path), 0.001));
}

TEST(Ingest, FillsNanVoidsOfFloatRasters)
{
    ScratchDir dir;
    const GdalBand src = everest();
    std::vector<double> values = src.values;
    for (int y = 50; y < 60; ++y)
        for (int x = 100; x < 113; ++x)
            values[size_t(y) * src.width + x] = NAN;
    const std::string path = dir.path("nan_voids.tif");
    RasterSetup setup;
    setup.nodata = NAN;
    writeTestRaster(path, "GTiff", GDT_Float64, src.width, src.height, values, setup);
    const ElevationRaster r = ingestRaster(path);
    EXPECT_EQ(r.stats.voids_filled, 130);
    EXPECT_TRUE(r.stats.exact);
    for (size_t i = 0; i < values.size(); ++i) {
        const double m = r.quantization.toMetres(r.grid.codes[i]);
        if (std::isnan(values[i])) {
            ASSERT_GE(m, r.stats.min_metres);
            ASSERT_LE(m, r.stats.max_metres);
        } else {
            ASSERT_EQ(m, values[i]);
        }
    }
}

TEST(Ingest, TreatsMaskedSamplesAsVoids)
{
    ScratchDir dir;
    const GdalBand src = everest();
    const std::string path = dir.path("masked.tif");
    RasterSetup setup;
    setup.customize = [&](GDALDatasetH ds) {
        ASSERT_EQ(GDALCreateDatasetMaskBand(ds, GMF_PER_DATASET), CE_None);
        GDALRasterBandH mask = GDALGetMaskBand(GDALGetRasterBand(ds, 1));
        std::vector<uint8_t> m(src.values.size(), 255);
        for (int y = 10; y < 20; ++y)
            for (int x = 30; x < 35; ++x)
                m[size_t(y) * src.width + x] = 0;
        ASSERT_EQ(GDALRasterIO(mask, GF_Write, 0, 0, src.width, src.height, m.data(), src.width,
                               src.height, GDT_Byte, 0, 0),
                  CE_None);
    };
    writeTestRaster(path, "GTiff", GDT_Int16, src.width, src.height, src.values, setup);
    const ElevationRaster r = ingestRaster(path);
    EXPECT_EQ(r.stats.voids_filled, 50);
    EXPECT_EQ(r.stats.valid_samples, int64_t(src.values.size()) - 50);
    for (int y = 10; y < 20; ++y)
        for (int x = 30; x < 35; ++x) {
            const double m = r.quantization.toMetres(r.grid.at(x, y));
            EXPECT_GE(m, r.stats.min_metres);
            EXPECT_LE(m, r.stats.max_metres);
        }
    EXPECT_EQ(r.quantization.toMetres(r.grid.at(0, 0)), src.at(0, 0));
}

TEST(Ingest, ConvertsFeetToMetres)
{
    ScratchDir dir;
    const GdalBand src = everest();
    std::vector<double> feet(src.values.size());
    for (size_t i = 0; i < feet.size(); ++i)
        feet[i] = std::round(src.values[i] / 0.3048);

    const std::string path = dir.path("feet.tif");
    RasterSetup setup;
    setup.unit = "ft";
    writeTestRaster(path, "GTiff", GDT_Int16, src.width, src.height, feet, setup);
    const ElevationRaster r = ingestRaster(path);
    EXPECT_EQ(r.geo.vertical_units, "ft");
    EXPECT_EQ(r.stats.z_scale, 0.3048);
    EXPECT_TRUE(r.stats.exact);
    EXPECT_NEAR(r.quantization.scale, 0.3048, 1e-15);
    for (size_t i = 0; i < feet.size(); ++i)
        ASSERT_NEAR(r.quantization.toMetres(r.grid.codes[i]), feet[i] * 0.3048, 1e-9);

    const std::string survey = dir.path("us_feet.tif");
    setup.unit = "US survey foot";
    writeTestRaster(survey, "GTiff", GDT_Int16, src.width, src.height, feet, setup);
    EXPECT_DOUBLE_EQ(ingestRaster(survey).stats.z_scale, 1200.0 / 3937.0);

    // An explicit z_scale replaces what the band says.
    IngestOptions options;
    options.z_scale = 1.0;
    EXPECT_EQ(ingestRaster(path, options).stats.z_scale, 1.0);
}

TEST(Ingest, AppliesTheBandsScaleAndOffset)
{
    ScratchDir dir;
    const GdalBand src = everest();
    const std::string path = dir.path("scaled.tif");
    RasterSetup setup;
    setup.scale = 0.5;
    setup.offset = -100.0;
    setup.unit = "metre";
    writeTestRaster(path, "GTiff", GDT_Int16, src.width, src.height, src.values, setup);
    const ElevationRaster r = ingestRaster(path);
    EXPECT_EQ(r.stats.z_scale, 0.5);
    EXPECT_EQ(r.stats.z_offset, -100.0);
    EXPECT_EQ(r.stats.min_metres, 3369 * 0.5 - 100);
    for (size_t i = 0; i < src.values.size(); ++i)
        ASSERT_EQ(r.quantization.toMetres(r.grid.codes[i]), src.values[i] * 0.5 - 100);
}

TEST(Ingest, UsesProjectedLinearUnitsForSpacing)
{
    ScratchDir dir;
    const GdalBand src = everest();
    RasterSetup setup;
    setup.geotransform = std::array<double, 6>{500000, 30, 0, 3100000, 0, -30};
    setup.epsg = 32645; // UTM 45N, metres
    const std::string utm = dir.path("utm.tif");
    writeTestRaster(utm, "GTiff", GDT_Int16, src.width, src.height, src.values, setup);
    const ElevationRaster r = ingestRaster(utm);
    EXPECT_FALSE(r.geo.geographic);
    EXPECT_FALSE(r.geo.spacing_from_user);
    EXPECT_DOUBLE_EQ(r.geo.spacing_x, 30.0);
    EXPECT_DOUBLE_EQ(r.geo.spacing_y, 30.0);

    setup.geotransform = std::array<double, 6>{6000000, 10, 0, 2000000, 0, -10};
    setup.epsg = 2227; // California zone 3, US survey feet
    const std::string feet = dir.path("stateplane.tif");
    writeTestRaster(feet, "GTiff", GDT_Int16, src.width, src.height, src.values, setup);
    EXPECT_NEAR(ingestRaster(feet).geo.spacing_x, 10 * 1200.0 / 3937.0, 1e-9);
}

TEST(Ingest, FillsVoidsFartherFromDataThanOneSearchReaches)
{
    // A nodata collar 220 samples wide along the west edge, like sea or a clipped DEM:
    // its far side is beyond one fill pass's search distance.
    ScratchDir dir;
    const GdalBand src = everest();
    std::vector<double> values = src.values;
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < 220; ++x)
            values[size_t(y) * src.width + x] = -32768;
    const std::string path = dir.path("collar.tif");
    RasterSetup setup;
    setup.nodata = -32768;
    writeTestRaster(path, "GTiff", GDT_Int16, src.width, src.height, values, setup);
    IngestOptions fill_all;
    fill_all.fill_voids = VoidFill::All; // the collar touches the border: filled only on request
    const ElevationRaster r = ingestRaster(path, fill_all);
    EXPECT_EQ(r.stats.voids_filled, 220 * src.height);
    EXPECT_EQ(r.stats.voids_kept, 0);
    EXPECT_TRUE(r.nodata.empty());
    // By default (interior) the same collar stays nodata, its codes filled all the same.
    const ElevationRaster kept = ingestRaster(path);
    EXPECT_EQ(kept.stats.voids_filled, 0);
    EXPECT_EQ(kept.stats.voids_kept, 220 * src.height);
    EXPECT_EQ(kept.stats.fill_voids, VoidFill::Interior);
    ASSERT_EQ(kept.nodata.size(), values.size());
    for (size_t i = 0; i < values.size(); ++i)
        ASSERT_EQ(kept.nodata[i] != 0, values[i] == -32768) << i;
    EXPECT_EQ(kept.grid.codes, r.grid.codes);
    for (size_t i = 0; i < values.size(); ++i) {
        const double m = r.quantization.toMetres(r.grid.codes[i]);
        if (values[i] == -32768) {
            ASSERT_GE(m, r.stats.min_metres) << i;
            ASSERT_LE(m, r.stats.max_metres) << i;
        } else {
            ASSERT_EQ(m, values[i]);
        }
    }
}

TEST(Ingest, FillsVoidsWhenValidCodesUseAll16Bits)
{
    // No spare code to mark voids with: the fill must still reach every void.
    ScratchDir dir;
    const int w = 64, h = 48;
    std::vector<double> values(size_t(w) * h);
    for (size_t i = 0; i < values.size(); ++i)
        values[i] = double((i * 40503u) % 65536);
    values[5] = 0;
    values[6] = 65535;
    const std::string path = dir.path("full_range_masked.tif");
    RasterSetup setup;
    setup.customize = [&](GDALDatasetH ds) {
        ASSERT_EQ(GDALCreateDatasetMaskBand(ds, GMF_PER_DATASET), CE_None);
        std::vector<uint8_t> m(values.size(), 255);
        for (int y = 20; y < 30; ++y)
            for (int x = 0; x < 40; ++x)
                m[size_t(y) * w + x] = 0;
        ASSERT_EQ(GDALRasterIO(GDALGetMaskBand(GDALGetRasterBand(ds, 1)), GF_Write, 0, 0, w, h,
                               m.data(), w, h, GDT_Byte, 0, 0),
                  CE_None);
    };
    writeTestRaster(path, "GTiff", GDT_UInt16, w, h, values, setup);
    IngestOptions fill_all;
    fill_all.fill_voids = VoidFill::All; // the voids touch the west border
    const ElevationRaster r = ingestRaster(path, fill_all);
    EXPECT_EQ(r.stats.voids_filled, 400);
    EXPECT_EQ(r.stats.min_metres, 0.0);
    EXPECT_EQ(r.stats.max_metres, 65535.0);
    EXPECT_EQ(r.grid.at(0, 0), values[0]);
}

} // namespace
} // namespace ridge::io

namespace ridge::io {
namespace {

// GDAL's own translation of the Everest crop into another format.
std::string translate(const std::string& driver, const std::string& path)
{
    GDALAllRegister();
    GDALDatasetH src = GDALOpen(test::dataPath("everest_crop.tif").c_str(), GA_ReadOnly);
    GDALDatasetH out = GDALCreateCopy(GDALGetDriverByName(driver.c_str()), path.c_str(), src, FALSE,
                                      nullptr, nullptr, nullptr);
    GDALClose(src);
    if (!out)
        throw std::runtime_error("test: cannot write " + path);
    GDALClose(out);
    return path;
}

} // namespace

// The same real terrain through other formats GDAL reads: identical heights and spacing.
TEST(Ingest, AsciiGridAndNetcdfGiveTheSameTerrainAsGeoTiff)
{
    test::ScratchDir dir;
    const ElevationRaster tiff = ingestRaster(test::dataPath("everest_crop.tif"));
    for (const auto& [driver, name] :
         {std::pair{"AAIGrid", "everest.asc"}, std::pair{"netCDF", "everest.nc"}}) {
        const ElevationRaster other = ingestRaster(translate(driver, dir.path(name)));
        ASSERT_EQ(other.grid.width, tiff.grid.width) << driver;
        ASSERT_EQ(other.grid.height, tiff.grid.height) << driver;
        EXPECT_TRUE(other.stats.exact) << driver;
        for (size_t i = 0; i < tiff.grid.codes.size(); ++i)
            ASSERT_EQ(other.quantization.toMetres(other.grid.codes[i]),
                      tiff.quantization.toMetres(tiff.grid.codes[i]))
                << driver << " sample " << i;
        EXPECT_NEAR(other.geo.spacing_x, tiff.geo.spacing_x, 1e-6 * tiff.geo.spacing_x) << driver;
        EXPECT_NEAR(other.geo.spacing_y, tiff.geo.spacing_y, 1e-6 * tiff.geo.spacing_y) << driver;
    }
}

} // namespace ridge::io

namespace ridge::io {

TEST(Ingest, FillVoidsModesAreNamedAndValidated)
{
    EXPECT_EQ(parseVoidFill("all"), VoidFill::All);
    EXPECT_EQ(parseVoidFill("interior"), VoidFill::Interior);
    EXPECT_EQ(parseVoidFill("none"), VoidFill::None);
    EXPECT_STREQ(voidFillName(VoidFill::None), "none");
    try {
        parseVoidFill("some");
        FAIL();
    } catch (const ridge::Error& e) {
        EXPECT_STREQ(e.what(), "fill_voids is 'some': must be all, interior or none");
    }
    IngestOptions o;
    o.fill_voids = static_cast<VoidFill>(7);
    EXPECT_THROW(o.validate(), ridge::Error);
}

} // namespace ridge::io
