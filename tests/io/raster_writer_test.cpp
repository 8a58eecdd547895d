// writeGeoTiff / writePng: round trips through GDAL, atomic failure.
#include "io_test_support.h"
#include "test_support.h"

#include "ridge/core/error.h"
#include "ridge/io/raster_writer.h"

#include <gtest/gtest.h>

#include <cpl_string.h>
#include <cpl_vsi.h>

#include <filesystem>
#include <fstream>

namespace ridge::io {
namespace {

using test::readWithGdal;
using test::ScratchDir;

size_t filesIn(const std::filesystem::path& dir)
{
    size_t n = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir))
        ++n;
    return n;
}

TEST(Writer, GeoTiffRoundTripsValuesAndGeoreference)
{
    ScratchDir dir;
    const test::GdalBand everest = readWithGdal(test::dataPath("everest_crop.tif"));
    GeoReference geo;
    geo.has_geotransform = true;
    geo.geotransform = everest.geotransform;
    geo.crs_wkt = everest.wkt;
    const int w = 301, h = 203;
    std::vector<float> metres(size_t(w) * h);
    for (size_t i = 0; i < metres.size(); ++i)
        metres[i] = float(everest.values[i] + 0.25);

    const std::string path = dir.path("out.tif");
    writeGeoTiff(path, metres.data(), w, h, geo);
    EXPECT_EQ(filesIn(dir.dir()), 1u);

    const test::GdalBand back = readWithGdal(path);
    ASSERT_EQ(back.width, w);
    ASSERT_EQ(back.height, h);
    for (size_t i = 0; i < metres.size(); ++i)
        ASSERT_EQ(back.values[i], double(metres[i]));
    EXPECT_EQ(back.geotransform, everest.geotransform);
    EXPECT_EQ(back.unit, "m");
    OGRSpatialReferenceH a = OSRNewSpatialReference(back.wkt.c_str());
    OGRSpatialReferenceH b = OSRNewSpatialReference(everest.wkt.c_str());
    EXPECT_TRUE(OSRIsSame(a, b));
    OSRDestroySpatialReference(a);
    OSRDestroySpatialReference(b);

    GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
    ASSERT_NE(ds, nullptr);
    int bx = 0, by = 0;
    GDALGetBlockSize(GDALGetRasterBand(ds, 1), &bx, &by);
    EXPECT_EQ(bx, 256); // tiled
    const char* compression = GDALGetMetadataItem(ds, "COMPRESSION", "IMAGE_STRUCTURE");
    EXPECT_STREQ(compression, "DEFLATE");
    EXPECT_EQ(GDALGetRasterDataType(GDALGetRasterBand(ds, 1)), GDT_Float32);
    GDALClose(ds);
}

TEST(Writer, GeoTiffWithoutGeoreferenceHasNone)
{
    ScratchDir dir;
    std::vector<float> metres = {1, 2, 3, 4, 5, 6};
    const std::string path = dir.path("plain.tif");
    writeGeoTiff(path, metres.data(), 3, 2, GeoReference{});
    const test::GdalBand back = readWithGdal(path);
    EXPECT_FALSE(back.has_geotransform);
    EXPECT_TRUE(back.wkt.empty());
    EXPECT_EQ(back.values, std::vector<double>({1, 2, 3, 4, 5, 6}));
}

TEST(Writer, PngRoundTripsGreyRgbAndRgba)
{
    ScratchDir dir;
    const int w = 23, h = 17;
    for (int channels : {1, 3, 4}) {
        std::vector<uint8_t> pixels(size_t(w) * h * channels);
        for (size_t i = 0; i < pixels.size(); ++i)
            pixels[i] = uint8_t(i * 31 + channels);
        const std::string path = dir.path("image" + std::to_string(channels) + ".png");
        writePng(path, pixels.data(), w, h, channels);

        GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
        ASSERT_NE(ds, nullptr);
        ASSERT_EQ(GDALGetRasterCount(ds), channels);
        std::vector<uint8_t> back(pixels.size());
        ASSERT_EQ(GDALDatasetRasterIO(ds, GF_Read, 0, 0, w, h, back.data(), w, h, GDT_Byte,
                                      channels, nullptr, channels, w * channels, 1),
                  CE_None);
        GDALClose(ds);
        EXPECT_EQ(back, pixels) << channels << " channels";
    }
    // Only the three PNGs: no .aux.xml, no temporary left over.
    EXPECT_EQ(filesIn(dir.dir()), 3u);
}

TEST(Writer, FailureLeavesNothingBehind)
{
    ScratchDir dir;
    const std::string path = dir.path("missing_dir/out.tif");
    std::vector<float> metres(16, 1.0f);
    try {
        writeGeoTiff(path, metres.data(), 4, 4, GeoReference{});
        FAIL() << "writing into a missing directory succeeded";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    }
    std::vector<uint8_t> pixels(16, 7);
    const std::string png = dir.path("missing_dir/out.png");
    EXPECT_THROW(writePng(png, pixels.data(), 4, 4, 1), Error);
    EXPECT_THROW(writePng(dir.path("two.png"), pixels.data(), 4, 2, 2), Error);
    EXPECT_FALSE(std::filesystem::exists(dir.path("missing_dir")));
    EXPECT_EQ(filesIn(dir.dir()), 0u);
}

TEST(Writer, ReplacesAnExistingFileWhole)
{
    ScratchDir dir;
    const std::string path = dir.path("again.png");
    std::vector<uint8_t> big(64 * 64, 200), small(4, 9);
    writePng(path, big.data(), 64, 64, 1);
    writePng(path, small.data(), 2, 2, 1);
    GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
    ASSERT_NE(ds, nullptr);
    EXPECT_EQ(GDALGetRasterXSize(ds), 2);
    GDALClose(ds);
    EXPECT_EQ(filesIn(dir.dir()), 1u);
}

} // namespace
} // namespace ridge::io

namespace ridge::io {
namespace {

std::vector<double> ramp(int w, int h)
{
    std::vector<double> v(size_t(w) * h);
    for (size_t i = 0; i < v.size(); ++i)
        v[i] = double(i % 1000);
    return v;
}

// A driver that writes two files (ENVI: the raw samples and a .hdr): both appear, whole, and
// GDAL's memory files are gone afterwards.
TEST(Writer, RasterOfAMultiFileDriverPublishesEveryFile)
{
    ScratchDir dir;
    const int w = 40, h = 30;
    const std::vector<double> values = ramp(w, h);
    GeoReference geo;
    geo.has_geotransform = true;
    geo.geotransform = {500000, 30, 0, 4000000, 0, -30};
    const std::string path = dir.path("out.bin");
    writeRaster(path, values, w, h, sampleType("UInt16"), geo, {"ENVI", {}, 65535.0}, {});
    EXPECT_TRUE(std::filesystem::exists(dir.path("out.hdr")));
    EXPECT_EQ(std::filesystem::file_size(path), size_t(w) * h * 2);
    const test::GdalBand band = readWithGdal(path);
    EXPECT_EQ(band.values, values);
    EXPECT_EQ(band.geotransform, geo.geotransform);
    EXPECT_EQ(test::temporariesIn(dir.dir()), std::vector<std::string>{});
    char** left = VSIReadDir("/vsimem/");
    for (char** p = left; p && *p; ++p)
        EXPECT_NE(std::string(*p).rfind("ridge-write-", 0), 0u) << "left in /vsimem/: " << *p;
    CSLDestroy(left);
}

TEST(Writer, RasterRefusesBadFormatsTypesAndOptionsLeavingNothing)
{
    ScratchDir dir;
    const std::vector<double> values = ramp(8, 8);
    const std::string path = dir.path("out.tif");
    const auto refused = [&](const RasterFormat& format, const std::string& type,
                             const std::string& phrase) {
        try {
            writeRaster(path, values, 8, 8, sampleType(type), GeoReference{}, format, {});
            ADD_FAILURE() << "accepted: " << phrase;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
        }
        EXPECT_EQ(filesIn(dir.dir()), 0u) << phrase;
    };
    refused({"NoSuchDriver", {}, {}}, "Int16", "output_format 'NoSuchDriver': no such GDAL driver");
    refused({"GTiff", {"COMPRESS=NOPE"}, {}}, "Int16",
            "creation_options: GDAL's GTiff driver refuses");
    refused({"GTiff", {"=1"}, {}}, "Int16", "creation_options '=1': expected NAME=VALUE");
    refused({"GTiff", {}, 1e6}, "Int16", "nodata_value");
    refused({"PNG", {}, {}}, "Float32", "PNG driver doesn't support data type Float32");
    EXPECT_THROW(sampleType("CInt16"), Error);
    EXPECT_TRUE(sampleType("int16").holdsExactly(-32768));
    EXPECT_FALSE(sampleType("Int16").holdsExactly(0.5));
    EXPECT_FALSE(sampleType("Float32").holdsExactly(0.1));
    EXPECT_TRUE(sampleType("Float64").holdsExactly(0.1));
}

// A side-car that would land on an input is refused before anything is published.
TEST(Writer, RasterSideCarOverAnInputIsRefused)
{
    ScratchDir dir;
    const std::string input = dir.path("out.hdr");
    {
        std::ofstream(input) << "precious";
    }
    const std::vector<double> values = ramp(4, 4);
    EXPECT_THROW(writeRaster(dir.path("out.bin"), values, 4, 4, sampleType("Byte"), GeoReference{},
                             {"ENVI", {}, {}}, {input}),
                 Error);
    EXPECT_EQ(test::readFile(input), "precious");
    EXPECT_FALSE(std::filesystem::exists(dir.path("out.bin")));
}

} // namespace
} // namespace ridge::io
