// ingestRaster on the real SRTM crops in tests/data.
#include "io_test_support.h"
#include "test_support.h"

#include "ridge/io/raster_source.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::io {
namespace {

using test::dataPath;
using test::readWithGdal;

// Parallel and meridian arc lengths of one pixel at latitude `lat_deg` on WGS 84.
std::pair<double, double> wgs84Spacing(double lat_deg, double dlon_deg, double dlat_deg)
{
    const double a = 6378137.0;
    const double f = 1 / 298.257223563;
    const double e2 = f * (2 - f);
    const double phi = lat_deg * std::numbers::pi / 180;
    const double w = 1 - e2 * std::sin(phi) * std::sin(phi);
    const double n = a / std::sqrt(w);
    const double m = a * (1 - e2) / std::pow(w, 1.5);
    const double rad = std::numbers::pi / 180;
    return {n * std::cos(phi) * std::abs(dlon_deg) * rad, m * std::abs(dlat_deg) * rad};
}

TEST(Ingest, ReadsTheEverestCropExactly)
{
    const std::string path = dataPath("everest_crop.tif");
    const test::GdalBand source = readWithGdal(path);
    const ElevationRaster r = ingestRaster(path);

    EXPECT_EQ(r.source_path, path);
    ASSERT_EQ(r.grid.width, 301);
    ASSERT_EQ(r.grid.height, 203);
    ASSERT_EQ(r.grid.codes.size(), size_t{301} * 203);
    EXPECT_EQ(r.stats.data_type, "Int16");
    EXPECT_TRUE(r.stats.exact);
    EXPECT_EQ(r.quantization.max_error, 0.0);
    EXPECT_EQ(r.quantization.scale, 1.0);
    EXPECT_EQ(r.stats.voids_filled, 0);
    EXPECT_EQ(r.stats.valid_samples, 301 * 203);
    EXPECT_EQ(r.stats.min_metres, 3369.0);
    EXPECT_EQ(r.stats.max_metres, 8840.0); // the summit is in the crop
    for (int y = 0; y < r.grid.height; ++y)
        for (int x = 0; x < r.grid.width; ++x)
            ASSERT_EQ(r.quantization.toMetres(r.grid.at(x, y)), source.at(x, y))
                << "at (" << x << ", " << y << ")";
}

TEST(Ingest, MeasuresGeographicSpacingOnTheEllipsoid)
{
    const ElevationRaster r = ingestRaster(dataPath("everest_crop.tif"));
    const GeoReference& geo = r.geo;
    ASSERT_TRUE(geo.has_geotransform);
    EXPECT_TRUE(geo.geographic);
    EXPECT_FALSE(geo.spacing_from_user);
    EXPECT_NE(geo.crs_wkt.find("WGS"), std::string::npos);
    EXPECT_NEAR(geo.geotransform[1], 1.0 / 1200, 1e-12);
    EXPECT_NEAR(geo.geotransform[5], -1.0 / 1200, 1e-12);

    const double centre_lat = geo.geotransform[3] + geo.geotransform[5] * r.grid.height / 2.0;
    EXPECT_NEAR(centre_lat, 27.9, 0.05);
    const auto [sx, sy] = wgs84Spacing(centre_lat, geo.geotransform[1], geo.geotransform[5]);
    EXPECT_NEAR(geo.spacing_x, sx, sx * 0.005);
    EXPECT_NEAR(geo.spacing_y, sy, sy * 0.005);
    EXPECT_NEAR(geo.spacing_x, 82.0, 0.5);
    EXPECT_NEAR(geo.spacing_y, 92.3, 0.5);
}

TEST(Ingest, ForcedSpacingOverridesTheGeoreference)
{
    IngestOptions options;
    options.spacing = 50.0;
    options.force_spacing = true;
    const ElevationRaster r = ingestRaster(dataPath("everest_crop.tif"), options);
    EXPECT_TRUE(r.geo.spacing_from_user);
    EXPECT_EQ(r.geo.spacing_x, 50.0);
    EXPECT_EQ(r.geo.spacing_y, 50.0);
    EXPECT_TRUE(r.geo.has_geotransform);

    options.force_spacing = false; // a georeferenced raster ignores a plain --spacing
    EXPECT_NEAR(ingestRaster(dataPath("everest_crop.tif"), options).geo.spacing_x, 82.0, 0.5);
}

TEST(Ingest, NegativeZScaleKeepsCodesAscendingWithHeight)
{
    IngestOptions options;
    options.z_scale = -1.0; // e.g. a depth raster
    const std::string path = dataPath("everest_crop.tif");
    const test::GdalBand source = readWithGdal(path);
    const ElevationRaster r = ingestRaster(path, options);
    EXPECT_GT(r.quantization.scale, 0.0);
    EXPECT_TRUE(r.stats.exact);
    EXPECT_EQ(r.stats.z_scale, -1.0);
    EXPECT_EQ(r.stats.min_metres, -8840.0);
    EXPECT_EQ(r.stats.max_metres, -3369.0);
    for (size_t i = 0; i < r.grid.codes.size(); ++i)
        ASSERT_EQ(r.quantization.toMetres(r.grid.codes[i]), -source.values[i]);
}

// 8-connected clusters of void samples.
std::vector<std::vector<size_t>> voidClusters(const test::GdalBand& b)
{
    std::vector<int> label(b.values.size(), -1);
    std::vector<std::vector<size_t>> clusters;
    for (size_t start = 0; start < b.values.size(); ++start) {
        if (!b.isNodata(start) || label[start] >= 0)
            continue;
        clusters.emplace_back();
        std::vector<size_t> stack{start};
        label[start] = static_cast<int>(clusters.size() - 1);
        while (!stack.empty()) {
            const size_t i = stack.back();
            stack.pop_back();
            clusters.back().push_back(i);
            const int x = static_cast<int>(i % b.width);
            const int y = static_cast<int>(i / b.width);
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx;
                    const int ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= b.width || ny >= b.height)
                        continue;
                    const size_t j = static_cast<size_t>(ny) * b.width + nx;
                    if (b.isNodata(j) && label[j] < 0) {
                        label[j] = label[start];
                        stack.push_back(j);
                    }
                }
        }
    }
    return clusters;
}

TEST(Ingest, FillsVoidsWithoutSpikes)
{
    const std::string path = dataPath("rainier_voids.tif");
    const test::GdalBand source = readWithGdal(path);
    ASSERT_TRUE(source.nodata.has_value());
    int64_t nodata_count = 0;
    double valid_min = INFINITY;
    double valid_max = -INFINITY;
    for (size_t i = 0; i < source.values.size(); ++i) {
        if (source.isNodata(i)) {
            ++nodata_count;
        } else {
            valid_min = std::min(valid_min, source.values[i]);
            valid_max = std::max(valid_max, source.values[i]);
        }
    }
    ASSERT_GE(nodata_count, 200);
    const auto clusters = voidClusters(source);
    ASSERT_GE(clusters.size(), 2u);

    const ElevationRaster r = ingestRaster(path);
    EXPECT_EQ(r.stats.voids_filled, nodata_count);
    EXPECT_EQ(r.stats.valid_samples, int64_t(source.values.size()) - nodata_count);
    EXPECT_TRUE(r.stats.exact);
    EXPECT_EQ(r.stats.min_metres, valid_min);
    EXPECT_EQ(r.stats.max_metres, valid_max);

    for (size_t i = 0; i < source.values.size(); ++i) {
        const double m = r.quantization.toMetres(r.grid.codes[i]);
        if (!source.isNodata(i)) {
            ASSERT_EQ(m, source.values[i]) << "valid sample " << i << " changed";
        } else {
            ASSERT_GE(m, valid_min);
            ASSERT_LE(m, valid_max);
        }
    }

    // Each filled sample must stay within the heights around its own void: a spike (or a
    // leftover nodata code) would leave that range.
    constexpr int kMargin = 2;
    for (const auto& cluster : clusters) {
        int x0 = source.width, y0 = source.height, x1 = -1, y1 = -1;
        for (size_t i : cluster) {
            const int x = int(i % source.width), y = int(i / source.width);
            x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
        double lo = INFINITY, hi = -INFINITY;
        for (int y = std::max(0, y0 - kMargin); y <= std::min(source.height - 1, y1 + kMargin); ++y)
            for (int x = std::max(0, x0 - kMargin); x <= std::min(source.width - 1, x1 + kMargin);
                 ++x) {
                const size_t j = size_t(y) * source.width + x;
                if (!source.isNodata(j))
                    lo = std::min(lo, source.values[j]), hi = std::max(hi, source.values[j]);
            }
        for (size_t i : cluster) {
            const double m = r.quantization.toMetres(r.grid.codes[i]);
            EXPECT_GE(m, lo) << "void sample (" << i % source.width << ", " << i / source.width
                             << ") of a " << cluster.size() << "-sample void";
            EXPECT_LE(m, hi) << "void sample (" << i % source.width << ", " << i / source.width
                             << ") of a " << cluster.size() << "-sample void";
        }
    }
}

} // namespace
} // namespace ridge::io
