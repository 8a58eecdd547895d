// Ingest refuses options outside their ranges, z-scales that make heights non-finite or larger
// than any height may be (naming the file, the z-scale and the resulting range), and
// georeferenced spacings beyond kMaxSpacingMetres; probeRaster sizes a raster without reading.
#include "io_test_support.h"
#include "test_support.h"

#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"

#include "error_expectations.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>

namespace ridge::io {
namespace {

using ridge::test::errorOf;
using ridge::test::expectPhrases;

using test::ScratchDir;

TEST(IngestRanges, OptionsOutsideTheirRangesAreNamedWithTheRange)
{
    const std::string path = test::dataPath("everest_crop.tif");
    IngestOptions o;
    o.spacing = 2e7;
    expectPhrases(errorOf([&] { ingestRaster(path, o); }),
                  {path, "spacing is 2e+07: must be a number in (0, 1e+07]"});
    o = {};
    o.z_offset = NAN;
    expectPhrases(errorOf([&] { ingestRaster(path, o); }), {path, "z_offset is nan"});
    o = {};
    o.z_scale = 1e-300;
    expectPhrases(errorOf([&] { ingestRaster(path, o); }),
                  {path, "z_scale is 1e-300: its magnitude must be a finite number >= 1e-09"});
    o = {};
    o.max_error = -1.0;
    expectPhrases(errorOf([&] { ingestRaster(path, o); }),
                  {path, "max_error is -1: must be a number in (0, 1e+07]"});
    EXPECT_THROW(CodeRowReader(path, o), Error);
    EXPECT_THROW(probeRaster(path, o), Error);
}

TEST(IngestRanges, AZScaleBeyondEveryHeightIsRefusedBeforeReadingInteger16Data)
{
    // Int16: every code of the type must map to a height the archive can hold.
    const std::string path = test::dataPath("everest_crop.tif");
    IngestOptions o;
    o.z_scale = 1e300;
    for (const auto& attempt : std::vector<std::function<void()>>{[&] { ingestRaster(path, o); },
                                                                  [&] { CodeRowReader(path, o); }})
        expectPhrases(errorOf(attempt),
                      {path, "z_scale 1e+300 and z_offset 0", "Int16 type's values [-32768, 32767]",
                       "heights [-3.2768e+304, 3.2767e+304] m", "±1e+07 m"});
    o.z_scale = 1000.0; // ±32.8e6 m: finite, still beyond
    expectPhrases(errorOf([&] { ingestRaster(path, o); }), {"heights [-32768000, 32767000] m"});
    o.z_scale = 300.0; // ±9.8e6 m: fits
    EXPECT_NO_THROW(ingestRaster(path, o));
}

TEST(IngestRanges, FloatDataIsJudgedByTheValuesItHas)
{
    ScratchDir dir;
    const std::string path = dir.path("float.tif");
    test::writeTestRaster(path, "GTiff", GDT_Float32, 4, 4, std::vector<double>(16, 3000.0));
    IngestOptions o;
    o.z_scale = 1e6; // 3e9 m
    expectPhrases(errorOf([&] { ingestRaster(path, o); }),
                  {path, "its values [3000, 3000]", "heights [3e+09, 3e+09] m"});
    o.z_scale = 1e3; // 3e6 m
    EXPECT_NO_THROW(ingestRaster(path, o));
    // The band's own scale counts like a given one.
    const std::string scaled = dir.path("scaled.tif");
    test::RasterSetup setup;
    setup.scale = 1e300;
    test::writeTestRaster(scaled, "GTiff", GDT_Float32, 4, 4, std::vector<double>(16, 3000.0),
                          setup);
    expectPhrases(errorOf([&] { ingestRaster(scaled); }),
                  {scaled, "z_scale 1e+300", "[3000, 3000]"});
}

TEST(IngestRanges, AGeoreferencedSpacingBeyondTheLimitIsRefused)
{
    ScratchDir dir;
    const std::string path = dir.path("huge_pixels.tif");
    test::RasterSetup setup;
    setup.epsg = 32633; // UTM 33N, metres
    setup.geotransform = std::array<double, 6>{500000, 5e7, 0, 5e6, 0, -5e7};
    test::writeTestRaster(path, "GTiff", GDT_Int16, 4, 4, std::vector<double>(16, 1.0), setup);
    expectPhrases(errorOf([&] { ingestRaster(path); }),
                  {path, "ground spacing its georeferencing gives", "(0, 1e+07]"});
    EXPECT_THROW(CodeRowReader(path, {}), Error);
}

TEST(IngestRanges, ProbingAMillionByAMillionRasterReadsNothing)
{
    ScratchDir dir;
    const std::string path = dir.path("huge.vrt");
    std::ofstream(path) << "<VRTDataset rasterXSize=\"1000000\" rasterYSize=\"1000000\">\n"
                           "  <VRTRasterBand dataType=\"Int16\" band=\"1\"/>\n</VRTDataset>\n";
    const RasterProbe p = probeRaster(path);
    EXPECT_EQ(p.width, 1000000);
    EXPECT_EQ(p.height, 1000000);
    EXPECT_EQ(p.data_type, "Int16");
    EXPECT_TRUE(p.direct_codes);
    EXPECT_EQ(p.strip_extra_bytes_per_sample, 0);
    EXPECT_GT(p.block_cache_bytes, 0);

    const RasterProbe everest = probeRaster(test::dataPath("everest_crop.tif"));
    EXPECT_EQ(everest.width, 301);
    EXPECT_TRUE(everest.declares_nodata);
}

} // namespace
} // namespace ridge::io
