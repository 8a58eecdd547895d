#include "ridge/lod/camera_path.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

using namespace ridge;
using namespace ridge::lod;

namespace {
const TerrainFrame kFrame(PyramidGeometry(1001, 801, 33), 10.0, 10.0);
double flatGround(double, double)
{
    return 100.0;
}
} // namespace

TEST(CameraPath, FlyoverMovesAtTheSpeedAboveTheGroundAndIsTheSameEveryRun)
{
    CameraPathSettings s;
    s.speed_mps = 600.0;
    const auto a = makeCameraPath(kFrame, 0, 500, flatGround, s, 30);
    const auto b = makeCameraPath(kFrame, 0, 500, flatGround, s, 30);
    ASSERT_EQ(a.size(), 30u);
    for (size_t k = 0; k < a.size(); ++k) {
        EXPECT_EQ(a[k].position, b[k].position);
        EXPECT_DOUBLE_EQ(a[k].position.z, 100.0 + s.height_above_ground);
        EXPECT_GT(a[k].position.x, 0.0);
        EXPECT_LT(a[k].position.x, kFrame.extentX());
    }
    EXPECT_NEAR(glm::length(a[1].position - a[0].position), 600.0 / 60.0, 1e-9);
}

TEST(CameraPath, OrbitCirclesTheCentreAndTeleportJumps)
{
    CameraPathSettings s;
    s.kind = "orbit";
    const auto o = makeCameraPath(kFrame, 0, 500, flatGround, s, 10);
    const glm::dvec2 c(0.5 * kFrame.extentX(), 0.5 * kFrame.extentY());
    for (const CameraPose& p : o)
        EXPECT_NEAR(glm::length(glm::dvec2(p.position) - c), 0.35 * kFrame.extentX(), 1e-6);
    s.kind = "teleport";
    s.teleport_every = 5;
    const auto t = makeCameraPath(kFrame, 0, 500, flatGround, s, 12);
    EXPECT_GT(glm::length(t[5].position - t[4].position), 10.0 * s.speed_mps * s.frame_seconds);
    EXPECT_NEAR(glm::length(t[4].position - t[3].position), s.speed_mps * s.frame_seconds, 1e-6);
}

TEST(CameraPath, ReadsPosesFromAFileAndNamesTheLineOfABadOne)
{
    const std::string good = ::testing::TempDir() + "/ridge_path_good.txt";
    const std::string bad = ::testing::TempDir() + "/ridge_path_bad.txt";
    std::ofstream(good) << "# x y z lx ly lz\n1 2 3 4 5 6\n7 8 9 10 11 12\n";
    std::ofstream(bad) << "1 2 3 4 5 6\n1 2 three 4 5 6\n";
    CameraPathSettings s;
    s.kind = good;
    const auto p = makeCameraPath(kFrame, 0, 500, flatGround, s, 3);
    ASSERT_EQ(p.size(), 3u);
    EXPECT_EQ(p[2].position, p[0].position) << "the file repeats";
    s.kind = bad;
    try {
        makeCameraPath(kFrame, 0, 500, flatGround, s, 3);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(bad + ":2:"), std::string::npos) << e.what();
    }
    s.kind = "/nonexistent/path.txt";
    EXPECT_THROW(makeCameraPath(kFrame, 0, 500, flatGround, s, 3), Error);
    std::remove(good.c_str());
    std::remove(bad.c_str());
}

TEST(CameraPath, LonLatPosesGoThroughTheGeographicConversion)
{
    const std::string file = ::testing::TempDir() + "/ridge_path_lonlat.txt";
    std::ofstream(file) << "lonlat 86.9 27.9 9000 86.95 27.95 5000\n1 2 3 4 5 6\n";
    CameraPathSettings s;
    s.kind = file;
    try {
        makeCameraPath(kFrame, 0, 500, flatGround, s, 2);
        FAIL() << "no conversion given";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(file + ":1:"), std::string::npos) << e.what();
    }
    // Any conversion will do for the parser: a plain linear map, checked exactly.
    s.from_lon_lat = [](double lon, double lat, double h) {
        return glm::dvec3((lon - 86.0) * 1000.0, (lat - 27.0) * 1000.0, h);
    };
    const auto p = makeCameraPath(kFrame, 0, 500, flatGround, s, 2);
    ASSERT_EQ(p.size(), 2u);
    EXPECT_NEAR(p[0].position.x, 900.0, 1e-9);
    EXPECT_NEAR(p[0].position.y, 900.0, 1e-9);
    EXPECT_EQ(p[0].position.z, 9000.0);
    EXPECT_NEAR(p[0].look_at.x, 950.0, 1e-9);
    EXPECT_EQ(p[0].look_at.z, 5000.0);
    EXPECT_EQ(p[1].position, glm::dvec3(1, 2, 3));
    // A conversion's error names the line.
    std::ofstream(file) << "lonlat 86.9 27.9 9000 86.95 27.95\n";
    try {
        makeCameraPath(kFrame, 0, 500, flatGround, s, 1);
        FAIL() << "5 numbers";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(":1: expected lonlat and 6 numbers"),
                  std::string::npos)
            << e.what();
    }
    std::remove(file.c_str());
}
