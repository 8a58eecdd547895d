// CodeRowReader: the same codes and quantization as ingestRaster, rows on demand.
#include "io_test_support.h"
#include "test_support.h"

#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace ridge::io {
namespace {

using test::dataPath;
using test::ScratchDir;

// Reads every row in strips of `strip` rows; returns the codes and the voids reported.
std::pair<std::vector<uint16_t>, int64_t> readAll(CodeRowReader& reader, int strip)
{
    std::vector<uint16_t> codes(size_t(reader.width()) * reader.height());
    int64_t voids = 0;
    for (int y0 = 0; y0 < reader.height(); y0 += strip) {
        const int rows = std::min(strip, reader.height() - y0);
        voids += reader.readRows(y0, rows, codes.data() + size_t(y0) * reader.width());
    }
    return {codes, voids};
}

TEST(CodeRowReader, MatchesIngestOnTheEverestCrop)
{
    const std::string path = dataPath("everest_crop.tif");
    const ElevationRaster ingested = ingestRaster(path);
    CodeRowReader reader(path, {});
    EXPECT_EQ(reader.width(), ingested.grid.width);
    EXPECT_EQ(reader.height(), ingested.grid.height);
    EXPECT_EQ(reader.quantization().scale, ingested.quantization.scale);
    EXPECT_EQ(reader.quantization().offset, ingested.quantization.offset);
    EXPECT_EQ(reader.quantization().max_error, 0.0);
    EXPECT_EQ(reader.geo().spacing_x, ingested.geo.spacing_x);
    EXPECT_EQ(reader.geo().crs_wkt, ingested.geo.crs_wkt);
    EXPECT_EQ(reader.stats().valid_samples, 0);

    const auto [codes, voids] = readAll(reader, 29); // strips cut across the 13-row blocks
    EXPECT_EQ(voids, 0);
    EXPECT_EQ(codes, ingested.grid.codes);
    const IngestStats stats = reader.stats();
    EXPECT_EQ(stats.data_type, "Int16");
    EXPECT_EQ(stats.valid_samples, ingested.stats.valid_samples);
    EXPECT_EQ(stats.min_metres, ingested.stats.min_metres);
    EXPECT_EQ(stats.max_metres, ingested.stats.max_metres);
    EXPECT_TRUE(stats.exact);
    EXPECT_EQ(stats.voids_filled, 0);
}

TEST(CodeRowReader, RowsReadTwiceAreCountedOnce)
{
    // The streaming build reads strips of 2C+1 rows that share their last row with the next
    // strip; the archive's metadata (valid_samples) must still count each sample once.
    const std::string path = dataPath("everest_crop.tif");
    CodeRowReader reader(path, {});
    std::vector<uint16_t> strip(size_t(reader.width()) * 33),
        whole(size_t(reader.width()) * reader.height());
    for (int y0 = 0; y0 + 1 < reader.height(); y0 += 32) {
        const int rows = std::min(33, reader.height() - y0);
        reader.readRows(y0, rows, strip.data());
        std::copy(strip.begin(), strip.begin() + size_t(rows) * reader.width(),
                  whole.begin() + size_t(y0) * reader.width());
    }
    reader.readRows(0, reader.height(), whole.data()); // all of it again
    EXPECT_EQ(reader.stats().valid_samples, int64_t(reader.width()) * reader.height());
    EXPECT_EQ(whole, ingestRaster(path).grid.codes);
}

TEST(CodeRowReader, ReportsVoidsInsteadOfFillingThem)
{
    const std::string path = dataPath("rainier_voids.tif");
    const test::GdalBand source = test::readWithGdal(path);
    CodeRowReader reader(path, {});
    const auto [codes, voids] = readAll(reader, 64);
    int64_t nodata = 0;
    for (size_t i = 0; i < source.values.size(); ++i) {
        if (source.isNodata(i))
            ++nodata;
        else
            ASSERT_EQ(reader.quantization().toMetres(codes[i]), source.values[i]);
    }
    EXPECT_EQ(voids, nodata);
    EXPECT_EQ(reader.stats().valid_samples, int64_t(source.values.size()) - nodata);
}

TEST(CodeRowReader, QuantizesFloatsExactlyAsIngestDoes)
{
    ScratchDir dir;
    const test::GdalBand src = test::readWithGdal(dataPath("everest_crop.tif"));
    std::vector<double> values(src.values.size());
    for (size_t i = 0; i < values.size(); ++i)
        values[i] = src.values[i] / 3.7 + 0.011 * (i % 5);
    const std::string path = dir.path("fractional.tif");
    test::writeTestRaster(path, "GTiff", GDT_Float32, src.width, src.height, values);

    IngestOptions options;
    options.max_error = 0.05;
    const ElevationRaster ingested = ingestRaster(path, options);
    CodeRowReader reader(path, options);
    EXPECT_EQ(reader.quantization().scale, ingested.quantization.scale);
    EXPECT_EQ(reader.quantization().offset, ingested.quantization.offset);
    EXPECT_EQ(reader.quantization().max_error, ingested.quantization.max_error);
    EXPECT_GT(reader.quantization().max_error, 0.0);
    EXPECT_EQ(readAll(reader, 50).first, ingested.grid.codes);
    EXPECT_FALSE(reader.stats().exact);
    EXPECT_EQ(reader.stats().min_metres, ingested.stats.min_metres);
}

TEST(CodeRowReader, RefusesWhatIngestRefuses)
{
    ScratchDir dir;
    EXPECT_THROW(CodeRowReader(dir.path("missing.tif"), {}), Error);
    IngestOptions zero;
    zero.z_scale = 0.0;
    EXPECT_THROW(CodeRowReader(dataPath("everest_crop.tif"), zero), Error);
    CodeRowReader reader(dataPath("everest_crop.tif"), {});
    std::vector<uint16_t> row(reader.width());
    EXPECT_THROW(reader.readRows(reader.height(), 1, row.data()), Error);
}

} // namespace
} // namespace ridge::io

namespace ridge::io {
namespace {

// A sharded build's window reads a Float32 raster through the whole raster's code mapping:
// the same codes without a survey, and a value the mapping does not hold is refused.
TEST(CodeRowReader, APlannedCodeMappingGivesTheSameCodesAndRefusesOthers)
{
    const ScratchDir dir;
    const std::string path = dir.path("f.tif");
    std::vector<double> values(40 * 30);
    for (size_t i = 0; i < values.size(); ++i)
        values[i] = 100.0 + 0.37 * double(i % 97) + 0.011 * double(i / 40);
    test::writeTestRaster(path, "GTiff", GDT_Float32, 40, 30, values);
    CodeRowReader whole(path, {});
    const std::optional<CodeMapping> mapping = whole.codeMapping();
    ASSERT_TRUE(mapping.has_value());
    EXPECT_FALSE(mapping->exact);
    EXPECT_GT(mapping->quantization.max_error, 0.0);
    IngestOptions planned;
    planned.code_mapping = mapping;
    CodeRowReader part(path, planned);
    EXPECT_EQ(part.quantization().scale, whole.quantization().scale);
    EXPECT_EQ(part.quantization().max_error, whole.quantization().max_error);
    EXPECT_EQ(readAll(part, 7).first, readAll(whole, 30).first);

    // A mapping for a narrower range (another raster's) does not hold these values.
    CodeMapping narrow = *mapping;
    narrow.max_code = 1000;
    planned.code_mapping = narrow;
    CodeRowReader refused(path, planned);
    std::vector<uint16_t> codes(size_t(40) * 30);
    try {
        refused.readRows(0, 30, codes.data());
        FAIL() << "a value outside the planned mapping was read";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("not one the planned code mapping holds"),
                  std::string::npos)
            << e.what();
    }
    // 8/16-bit integer rasters have no mapping: their codes are their values.
    EXPECT_FALSE(CodeRowReader(dataPath("everest_crop.tif"), {}).codeMapping().has_value());
}

} // namespace
} // namespace ridge::io
