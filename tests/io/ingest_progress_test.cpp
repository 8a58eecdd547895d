// Progress reporting and cancellation of ingestRaster.
#include "io_test_support.h"
#include "test_support.h"

#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"

#include <gtest/gtest.h>

namespace ridge::io {
namespace {

using test::dataPath;

TEST(IngestProgress, ReportsMonotonicFractionsEndingAtOne)
{
    std::vector<double> seen;
    IngestOptions options;
    options.progress = [&seen](double f) {
        seen.push_back(f);
        return true;
    };
    ingestRaster(dataPath("rainier_voids.tif"), options);
    ASSERT_GE(seen.size(), 3u);
    for (size_t i = 1; i < seen.size(); ++i)
        EXPECT_GE(seen[i], seen[i - 1]);
    EXPECT_GE(seen.front(), 0.0);
    EXPECT_EQ(seen.back(), 1.0);
}

// Cancelling at the first report after `threshold` must throw Cancelled and close
// everything GDAL opened (datasets, the error handler, the cache limit).
void expectCleanCancel(const std::string& path, double threshold)
{
    const int open_before = test::openDatasetCount();
    const int64_t cache_before = GDALGetCacheMax64();
    IngestOptions options;
    bool asked = false;
    options.progress = [&](double f) {
        if (f < threshold)
            return true;
        asked = true;
        return false;
    };
    EXPECT_THROW(ingestRaster(path, options), Cancelled);
    EXPECT_TRUE(asked);
    EXPECT_EQ(test::openDatasetCount(), open_before);
    EXPECT_EQ(GDALGetCacheMax64(), cache_before);
    // ... and leave nothing behind that would disturb the next ingest.
    EXPECT_NO_THROW(ingestRaster(path));
}

TEST(IngestProgress, CancelWhileReadingThrowsCancelledAndCleansUp)
{
    expectCleanCancel(dataPath("everest_crop.tif"), 0.0);
}

TEST(IngestProgress, CancelWhileFillingVoidsThrowsCancelledAndCleansUp)
{
    expectCleanCancel(dataPath("rainier_voids.tif"), 0.92);
}

TEST(IngestProgress, ExceptionsFromTheCallbackPropagate)
{
    IngestOptions options;
    options.progress = [](double f) -> bool {
        if (f > 0.95)
            throw std::runtime_error("callback failed");
        return true;
    };
    EXPECT_THROW(ingestRaster(dataPath("rainier_voids.tif"), options), std::runtime_error);
}

} // namespace
} // namespace ridge::io
