// Every input ingestRaster must refuse, and how it explains itself: the message starts with
// the path and names the problem.
#include "io_test_support.h"
#include "test_support.h"

#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"

#include <gtest/gtest.h>

#include <fstream>

namespace ridge::io {
namespace {

using test::RasterSetup;
using test::ScratchDir;
using test::writeTestRaster;

// The Error ingestRaster throws for `path` (fails the test if it throws nothing).
std::string ingestError(const std::string& path, const IngestOptions& options = {})
{
    try {
        ingestRaster(path, options);
    } catch (const Cancelled&) {
        ADD_FAILURE() << "cancelled instead of an error";
    } catch (const Error& e) {
        return e.what();
    }
    ADD_FAILURE() << path << " was accepted";
    return {};
}

void expectMessage(const std::string& message, const std::string& path, const std::string& phrase)
{
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(phrase), std::string::npos) << message;
}

std::vector<double> ramp(int w, int h, double step = 1.0)
{
    std::vector<double> v(size_t(w) * h);
    for (size_t i = 0; i < v.size(); ++i)
        v[i] = double(i) * step;
    return v;
}

TEST(IngestErrors, NamesAMissingFile)
{
    ScratchDir dir;
    const std::string path = dir.path("no_such_file.tif");
    expectMessage(ingestError(path), path, "cannot open");
}

TEST(IngestErrors, RejectsAFileGdalDoesNotRecognise)
{
    ScratchDir dir;
    const std::string path = dir.path("garbage.tif");
    std::ofstream(path) << "This is not a raster, only a line of prose.\n";
    const std::string message = ingestError(path);
    expectMessage(message, path, "cannot open");
    EXPECT_NE(message.find("not recognized"), std::string::npos) << message;
}

TEST(IngestErrors, RejectsARasterWithoutBands)
{
    // A GeoPackage holding two raster tables opens as a container: subdatasets, no band.
    ScratchDir dir;
    const std::string path = dir.path("two_tables.gpkg");
    RasterSetup first;
    first.geotransform = std::array<double, 6>{86, 0.01, 0, 28, 0, -0.01};
    first.epsg = 4326;
    first.creation_options = {"RASTER_TABLE=a"};
    writeTestRaster(path, "GPKG", GDT_Byte, 16, 16, ramp(16, 16), first);
    RasterSetup second = first;
    second.creation_options = {"RASTER_TABLE=b", "APPEND_SUBDATASET=YES"};
    writeTestRaster(path, "GPKG", GDT_Byte, 16, 16, ramp(16, 16), second);
    const std::string message = ingestError(path);
    expectMessage(message, path, "no raster band");
    EXPECT_NE(message.find("subdataset"), std::string::npos) << message;
}

TEST(IngestErrors, RejectsARasterSmallerThan2x2)
{
    ScratchDir dir;
    const std::string path = dir.path("thin.tif");
    writeTestRaster(path, "GTiff", GDT_Int16, 1, 5, ramp(1, 5));
    expectMessage(ingestError(path), path, "1x5");
    expectMessage(ingestError(path), path, "too small");
}

TEST(IngestErrors, RejectsAnAllNodataRaster)
{
    ScratchDir dir;
    const std::string path = dir.path("all_nodata.tif");
    RasterSetup setup;
    setup.nodata = -32768;
    writeTestRaster(path, "GTiff", GDT_Int16, 8, 6, std::vector<double>(48, -32768), setup);
    expectMessage(ingestError(path), path, "all samples are nodata");

    const std::string nan_path = dir.path("all_nan.tif");
    setup.nodata = NAN;
    writeTestRaster(nan_path, "GTiff", GDT_Float32, 8, 6, std::vector<double>(48, NAN), setup);
    expectMessage(ingestError(nan_path), nan_path, "all samples are nodata");
}

TEST(IngestErrors, NamesTheFirstUndeclaredNonFiniteSample)
{
    ScratchDir dir;
    const std::string path = dir.path("nan.tif");
    std::vector<double> values = ramp(10, 8, 0.5);
    values[2 * 10 + 3] = NAN;      // (3, 2)
    values[5 * 10 + 1] = INFINITY; // later
    writeTestRaster(path, "GTiff", GDT_Float32, 10, 8, values);
    const std::string message = ingestError(path);
    expectMessage(message, path, "non-finite");
    EXPECT_NE(message.find("(3, 2)"), std::string::npos) << message;
}

TEST(IngestErrors, RejectsInvalidOptions)
{
    const std::string path = test::dataPath("everest_crop.tif");
    IngestOptions zero_scale;
    zero_scale.z_scale = 0.0;
    expectMessage(ingestError(path, zero_scale), path, "z_scale");

    IngestOptions nan_scale;
    nan_scale.z_scale = NAN;
    expectMessage(ingestError(path, nan_scale), path, "z_scale");

    IngestOptions bad_spacing;
    bad_spacing.spacing = -1.0;
    expectMessage(ingestError(path, bad_spacing), path, "spacing");
    bad_spacing.spacing = INFINITY;
    expectMessage(ingestError(path, bad_spacing), path, "spacing");

    IngestOptions bad_error;
    bad_error.max_error = 0.0;
    expectMessage(ingestError(path, bad_error), path, "max_error");
}

TEST(IngestErrors, SuggestsAMaxErrorThatFits16Bits)
{
    ScratchDir dir;
    const std::string path = dir.path("wide_range.tif");
    const int w = 101, h = 100;
    std::vector<double> values(size_t(w) * h);
    for (size_t i = 0; i < values.size(); ++i)
        values[i] = double(i) * (10000.0 / double(values.size() - 1)) + 0.25; // 10000 m range
    writeTestRaster(path, "GTiff", GDT_Float64, w, h, values);
    IngestOptions options;
    options.max_error = 0.01;
    const std::string message = ingestError(path, options);
    expectMessage(message, path, "max_error");
    EXPECT_EQ(message.find("--max-error"), std::string::npos) << "a parameter, not a flag";
    EXPECT_NE(message.find("0.0763"), std::string::npos) << message;

    // ... and the suggestion does work.
    options.max_error = 0.0763;
    const ElevationRaster r = ingestRaster(path, options);
    EXPECT_LE(r.quantization.max_error, 0.0763);
}

} // namespace
} // namespace ridge::io
