// ReferenceRaster: the source's exact metres, voids as NaN, in strips.
#include "io_test_support.h"
#include "test_support.h"

#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ridge::io {
namespace {

using test::dataPath;
using test::readWithGdal;

TEST(ReferenceRaster, ReportsVoidsAsNanAndExactValuesElsewhere)
{
    const std::string path = dataPath("rainier_voids.tif");
    const test::GdalBand source = readWithGdal(path);
    ReferenceRaster reference(path, {});
    ASSERT_EQ(reference.width(), source.width);
    ASSERT_EQ(reference.height(), source.height);

    constexpr int kStrip = 100; // not a multiple of the fixture's 128-row blocks
    std::vector<double> strip(size_t(kStrip) * source.width);
    int64_t nan_count = 0;
    for (int y0 = 0; y0 < source.height; y0 += kStrip) {
        const int rows = std::min(kStrip, source.height - y0);
        reference.readRows(y0, rows, strip.data());
        for (int i = 0; i < rows * source.width; ++i) {
            const size_t s = size_t(y0) * source.width + i;
            if (source.isNodata(s)) {
                ASSERT_TRUE(std::isnan(strip[i])) << "sample " << s;
                ++nan_count;
            } else {
                ASSERT_EQ(strip[i], source.values[s]) << "sample " << s;
            }
        }
    }
    EXPECT_GE(nan_count, 200);
}

TEST(ReferenceRaster, AppliesZScaleAndOffsetLikeIngest)
{
    const std::string path = dataPath("everest_crop.tif");
    IngestOptions options;
    options.z_scale = 0.3048;
    options.z_offset = 10.0;
    ReferenceRaster reference(path, options);
    const ElevationRaster ingested = ingestRaster(path, options);
    std::vector<double> rows(size_t(3) * reference.width());
    reference.readRows(7, 3, rows.data());
    for (int i = 0; i < 3 * reference.width(); ++i) {
        const double code_metres =
            ingested.quantization.toMetres(ingested.grid.codes[7 * reference.width() + i]);
        ASSERT_NEAR(rows[i], code_metres, 1e-9);
    }
}

TEST(ReferenceRaster, RejectsRowsOutsideTheRaster)
{
    const std::string path = dataPath("everest_crop.tif");
    ReferenceRaster reference(path, {});
    std::vector<double> rows(size_t(2) * reference.width());
    EXPECT_THROW(reference.readRows(reference.height() - 1, 2, rows.data()), Error);
    EXPECT_THROW(reference.readRows(-1, 1, rows.data()), Error);
    EXPECT_THROW(ReferenceRaster(path + ".missing", {}), Error);
}

} // namespace
} // namespace ridge::io
