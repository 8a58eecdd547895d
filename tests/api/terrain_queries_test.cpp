// The public API's GL-free queries beyond one point: batches in every coordinate space and
// both resamplings, the asynchronous form, and cameras placed by longitude/latitude.
#include <ridge/ridge.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <future>
#include <random>
#include <string>
#include <vector>

namespace {

using ridge::test::dataPath;
using ridge::test::ScratchDir;

std::string build(const ScratchDir& dir, const std::string& source, const std::string& codec)
{
    ridge::BuildParameters p;
    p.patch_size = 33;
    p.codec = codec;
    if (codec == "progressive")
        p.max_error = 1.0;
    const std::string path = dir.path(source + "." + codec + ".ridge");
    ridge::build(dataPath(source), path, p);
    return path;
}

// Points over the raster and around it, in local metres.
std::vector<std::array<double, 2>> localPoints(const ridge::Terrain& terrain, int count)
{
    const ridge::TerrainInfo& info = terrain.info();
    const double w = double(info.width) * info.spacing_x, h = double(info.height) * info.spacing_y;
    std::mt19937 rng(41);
    std::uniform_real_distribution<double> x(-0.05 * w, 1.05 * w), y(-0.05 * h, 1.05 * h);
    std::vector<std::array<double, 2>> points;
    for (int k = 0; k < count; ++k)
        points.push_back({x(rng), y(rng)});
    return points;
}

TEST(TerrainQueries, BatchesAnswerWhatHeightAnswersInEverySpace)
{
    ScratchDir dir;
    for (const std::string& codec : {std::string("lossless"), std::string("progressive")}) {
        const ridge::Terrain terrain(build(dir, "everest_utm45.tif", codec));
        const int finest = terrain.info().levels - 1;
        const std::vector<std::array<double, 2>> local = localPoints(terrain, 3000);
        // The same points in every space.
        std::vector<std::array<double, 2>> lonlat, crs, pixel;
        const auto& gt = *terrain.info().geotransform;
        for (const auto& p : local) {
            lonlat.push_back(terrain.lonLatFromLocal(p[0], p[1]));
            const double column = p[0] / terrain.info().spacing_x + 0.5;
            const double line =
                double(terrain.info().height) - 0.5 - p[1] / terrain.info().spacing_y;
            pixel.push_back({column, line});
            crs.push_back(
                {gt[0] + column * gt[1] + line * gt[2], gt[3] + column * gt[4] + line * gt[5]});
        }
        for (const int level : {-1, 1}) {
            ridge::QueryParameters q;
            q.level = level;
            const std::vector<ridge::PointHeight> by_local = terrain.heights(local, q);
            q.coordinates = ridge::Coordinates::LonLat;
            const std::vector<ridge::PointHeight> by_lonlat = terrain.heights(lonlat, q);
            q.coordinates = ridge::Coordinates::Crs;
            const std::vector<ridge::PointHeight> by_crs = terrain.heights(crs, q);
            q.coordinates = ridge::Coordinates::Pixel;
            const std::vector<ridge::PointHeight> by_pixel = terrain.heights(pixel, q);
            int ok = 0, off = 0;
            for (size_t k = 0; k < local.size(); ++k) {
                const std::optional<double> expected =
                    level < 0 ? terrain.height(local[k][0], local[k][1])
                              : terrain.heightAtLevel(local[k][0], local[k][1], level);
                const ridge::PointHeight& h = by_local[k];
                ASSERT_EQ(h.status == ridge::HeightStatus::Ok, expected.has_value()) << k;
                EXPECT_EQ(h.level, level < 0 ? finest : level);
                if (expected) {
                    ASSERT_EQ(h.height, *expected) << k;
                    EXPECT_GE(h.error_bound, 0.0);
                    ++ok;
                } else {
                    EXPECT_EQ(h.status, ridge::HeightStatus::OffTerrain) << k;
                    EXPECT_TRUE(std::isnan(h.height));
                    ++off;
                }
                // Other spaces reach the same point through PROJ or the geotransform: the same
                // status, heights within a millimetre.
                for (const auto* other : {&by_lonlat, &by_crs, &by_pixel}) {
                    const ridge::PointHeight& o = (*other)[k];
                    ASSERT_EQ(o.status, h.status) << k;
                    if (expected) {
                        ASSERT_NEAR(o.height, h.height, 1e-3) << k;
                    }
                }
            }
            EXPECT_GT(ok, 2000);
            EXPECT_GT(off, 100);
        }
    }
}

TEST(TerrainQueries, NearestIsTheSampleOfThePixelAndNodataIsPerSample)
{
    ScratchDir dir;
    const ridge::Terrain terrain(build(dir, "everest_utm44.tif", "lossless")); // kept collar
    const ridge::TerrainInfo& info = terrain.info();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> px(0.0, double(info.width)),
        py(0.0, double(info.height));
    std::vector<std::array<double, 2>> points, centres;
    for (int k = 0; k < 5000; ++k) {
        const double p = px(rng), l = py(rng);
        points.push_back({p, l});
        centres.push_back({std::floor(p) + 0.5, std::floor(l) + 0.5});
    }
    ridge::QueryParameters q;
    q.coordinates = ridge::Coordinates::Pixel;
    q.resampling = ridge::Resampling::Nearest;
    const std::vector<ridge::PointHeight> nearest = terrain.heights(points, q);
    const std::vector<ridge::PointHeight> at_centre = terrain.heights(centres, q);
    q.resampling = ridge::Resampling::Bilinear;
    const std::vector<ridge::PointHeight> bilinear_centre = terrain.heights(centres, q);
    int nodata = 0, rim = 0;
    for (size_t k = 0; k < points.size(); ++k) {
        ASSERT_EQ(nearest[k].status, at_centre[k].status) << k;
        if (nearest[k].status == ridge::HeightStatus::Ok) {
            ASSERT_EQ(nearest[k].height, at_centre[k].height) << k;
            // At a sample centre bilinear reads the sample itself, where it draws.
            if (bilinear_centre[k].status == ridge::HeightStatus::Ok) {
                ASSERT_EQ(bilinear_centre[k].height, nearest[k].height) << k;
            } else {
                ++rim; // a data sample on the collar's rim: no drawn cell around it
            }
        } else {
            ASSERT_EQ(nearest[k].status, ridge::HeightStatus::NoData) << k;
            ASSERT_EQ(bilinear_centre[k].status, ridge::HeightStatus::NoData) << k;
            ++nodata;
        }
    }
    EXPECT_GT(nodata, 200);
    EXPECT_GT(rim, 0);
}

TEST(TerrainQueries, BadPointsAreReportedAndBadRequestsRefused)
{
    ScratchDir dir;
    const ridge::Terrain terrain(build(dir, "everest_crop.tif", "lossless"));
    const std::vector<std::array<double, 2>> points = {
        {86.9, 27.9}, {NAN, 27.9}, {86.9, 95.0}, {86.9, INFINITY}, {10.0, 10.0}, {86.95, 27.85}};
    ridge::QueryParameters q;
    q.coordinates = ridge::Coordinates::LonLat;
    const std::vector<ridge::PointHeight> h = terrain.heights(points, q);
    const ridge::HeightStatus expected[] = {
        ridge::HeightStatus::Ok,           ridge::HeightStatus::InvalidPoint,
        ridge::HeightStatus::InvalidPoint, ridge::HeightStatus::InvalidPoint,
        ridge::HeightStatus::OffTerrain,   ridge::HeightStatus::Ok};
    for (size_t k = 0; k < points.size(); ++k)
        EXPECT_EQ(h[k].status, expected[k]) << k;
    EXPECT_GT(h[0].height, 3000.0);
    // Requests the archive cannot take fail as a whole, by name.
    std::vector<ridge::PointHeight> short_out(2);
    EXPECT_THROW(terrain.heights(points, short_out, q), ridge::Error);
    q.level = terrain.info().levels;
    EXPECT_THROW(terrain.heights(points, q), ridge::Error);
    q.level = -2;
    EXPECT_THROW(terrain.heights(points, q), ridge::Error);
    EXPECT_THROW(terrain.heightsAsync({{1.0, 1.0}}, q), ridge::Error); // before it starts
    // No CRS: longitude/latitude are refused for the batch, pixels still answer.
    const std::string png = dir.path("plain.png");
    ASSERT_EQ(ridge::test::runShell("gdal_translate -q -of PNG -ot UInt16 -scale 3000 9000 0 "
                                    "65535 '" +
                                    dataPath("everest_crop.tif") + "' '" + png + "'")
                  .exit_code,
              0);
    std::filesystem::remove(png + ".aux.xml");
    ridge::BuildParameters p;
    p.patch_size = 33;
    ridge::build(png, dir.path("plain.ridge"), p);
    const ridge::Terrain plain(dir.path("plain.ridge"));
    ridge::QueryParameters ll;
    ll.coordinates = ridge::Coordinates::LonLat;
    EXPECT_THROW(plain.heights(points, ll), ridge::Error);
    ll.coordinates = ridge::Coordinates::Pixel;
    EXPECT_EQ(plain.heights({{{3.5, 4.5}}}, ll)[0].status, ridge::HeightStatus::Ok);
}

TEST(TerrainQueries, AsyncAnswersLikeTheSyncFormAndOutlivesItsTerrain)
{
    ScratchDir dir;
    const std::string path = build(dir, "everest_utm45.tif", "progressive");
    std::vector<std::array<double, 2>> points;
    std::vector<ridge::PointHeight> sync;
    std::future<std::vector<ridge::PointHeight>> pending;
    {
        const ridge::Terrain terrain(path);
        points = localPoints(terrain, 20000);
        ridge::QueryParameters q;
        q.resampling = ridge::Resampling::Nearest;
        pending = terrain.heightsAsync(points, q);
        sync = terrain.heights(points, q); // the Terrain in use meanwhile, then destroyed
    }
    const std::vector<ridge::PointHeight> async = pending.get();
    ASSERT_EQ(async.size(), sync.size());
    for (size_t k = 0; k < sync.size(); ++k) {
        ASSERT_EQ(async[k].status, sync[k].status) << k;
        if (sync[k].status == ridge::HeightStatus::Ok) {
            ASSERT_EQ(async[k].height, sync[k].height) << k;
        }
    }
    // An archive that disappears before the task opens it: the future rethrows.
    std::future<std::vector<ridge::PointHeight>> gone;
    {
        const std::string copy = dir.path("copy.ridge");
        std::filesystem::copy_file(path, copy);
        const ridge::Terrain terrain(copy);
        std::filesystem::remove(copy);
        gone = terrain.heightsAsync(points);
    }
    EXPECT_THROW(gone.get(), ridge::Error);
}

TEST(TerrainQueries, CamerasPlacedByLonLatHeadingAndPitch)
{
    ScratchDir dir;
    const ridge::Terrain terrain(build(dir, "everest_utm45.tif", "lossless"));
    // Above the summit, heading 200° (grid), 20° down.
    ridge::CameraParameters c;
    c.position_lonlat = {86.925, 27.988, 9500.0};
    c.heading_degrees = 200.0;
    c.pitch_degrees = -20.0;
    c.fov_y_degrees = 50.0;
    const ridge::CameraPose pose = terrain.cameraPose(c);
    const ridge::LocalPoint at = terrain.localFromLonLat(86.925, 27.988);
    EXPECT_NEAR(pose.position[0], at.x, 1e-6);
    EXPECT_NEAR(pose.position[1], at.y, 1e-6);
    EXPECT_EQ(pose.position[2], 9500.0);
    EXPECT_EQ(pose.fov_y_degrees, 50.0);
    const double dx = pose.look_at[0] - pose.position[0], dy = pose.look_at[1] - pose.position[1],
                 dz = pose.look_at[2] - pose.position[2];
    const double heading = std::atan2(dx, dy) * 180.0 / M_PI;
    const double pitch = std::atan2(dz, std::hypot(dx, dy)) * 180.0 / M_PI;
    EXPECT_NEAR(heading, 200.0 - 360.0, 1e-9);
    EXPECT_NEAR(pitch, -20.0, 1e-9);
    // Zone 45's central meridian is 87° E: at 86.925° true north is ~0.035° east of grid north.
    EXPECT_NEAR(terrain.convergenceDegrees(at.x, at.y),
                (87.0 - 86.925) * std::sin(27.988 * M_PI / 180.0), 2e-4);

    // 500 m above the ground, looking at a lon/lat point on the surface; without a look-at,
    // at the terrain's centre on its surface.
    ridge::CameraParameters g;
    g.position_lonlat = {86.90, 27.95, 500.0};
    g.above_ground = true;
    g.look_at_lonlat = {86.925, 27.988, NAN};
    const ridge::CameraPose over = terrain.cameraPose(g);
    const ridge::LocalPoint p = terrain.localFromLonLat(86.90, 27.95);
    EXPECT_NEAR(over.position[2], *terrain.height(p.x, p.y) + 500.0, 1e-6);
    EXPECT_NEAR(over.look_at[2], *terrain.height(at.x, at.y), 1e-6);
    g.look_at_lonlat.reset();
    const ridge::CameraPose centred = terrain.cameraPose(g);
    const double cx = 0.5 * double(terrain.info().width) * terrain.info().spacing_x;
    EXPECT_NEAR(centred.look_at[0], cx, terrain.info().spacing_x);

    // Refused by name: no position, both position forms, a heading without a pitch, a bad fov.
    auto refused = [&](const ridge::CameraParameters& bad, const char* what) {
        try {
            terrain.cameraPose(bad);
            ADD_FAILURE() << "placed a camera without complaint: " << what;
        } catch (const ridge::Error& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    refused(ridge::CameraParameters{}, "position");
    ridge::CameraParameters both = c;
    both.position = std::array<double, 3>{1.0, 2.0, 3.0};
    refused(both, "position");
    ridge::CameraParameters half = c;
    half.pitch_degrees.reset();
    refused(half, "pitch");
    ridge::CameraParameters wide = c;
    wide.fov_y_degrees = 180.0;
    refused(wide, "fov");
}

} // namespace
