// The lod entry points refuse NaN, infinite and out-of-range numbers with messages naming the
// parameter: the camera (the root guard of every renderer), selection settings, camera paths.
#include "ridge/lod/camera.h"
#include "ridge/lod/camera_path.h"
#include "ridge/lod/patch_quadtree.h"

#include "ridge/core/error.h"

#include "error_expectations.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>

using namespace ridge;
using namespace ridge::lod;

namespace {

using ridge::test::errorOf;
using ridge::test::expectError;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Camera camera(glm::dvec3 position, glm::dvec3 look_at = {0, 1e3, 0}, double fov = 60.0,
              double near_m = 1.0, double far_m = 1e6)
{
    return Camera(position, look_at, fov, {640, 360}, near_m, far_m);
}

PatchQuadtree flatTree()
{
    const PyramidGeometry g(257, 257, 33);
    std::vector<PatchBounds> bounds(size_t(g.patchCount()), PatchBounds{0.f, 100.f, 1.f});
    return PatchQuadtree(TerrainFrame(g, 10.0, 10.0), std::move(bounds));
}

} // namespace

TEST(CameraValidation, NanOrInfinitePositionsAndLookAtPointsAreRefusedByName)
{
    for (const glm::dvec3 bad : {glm::dvec3(kNan, 0, 0), glm::dvec3(0, kInf, 0),
                                 glm::dvec3(0, 0, -kInf), glm::dvec3(2e15, 0, 0)}) {
        expectError([&] { camera(bad); }, "camera position is (");
        expectError([&] { camera({0, 0, 0}, bad); }, "camera look-at point is (");
    }
    expectError([&] { camera({kNan, 0, 0}); }, "[-1e+15, 1e+15]");
    EXPECT_NO_THROW(camera({1e15, -1e15, 0}, {-1e15, 1e15, 0}));
}

TEST(CameraValidation, FieldOfViewAndClipPlanesMustBeFiniteAndOrdered)
{
    expectError([&] { camera({0, 0, 0}, {0, 1, 0}, kNan); }, "field of view");
    expectError([&] { camera({0, 0, 0}, {0, 1, 0}, 180.0); }, "(0, 180)");
    expectError([&] { camera({0, 0, 0}, {0, 1, 0}, 60.0, kNan); }, "near plane");
    expectError([&] { camera({0, 0, 0}, {0, 1, 0}, 60.0, 1.0, kInf); }, "far plane");
    expectError([&] { camera({0, 0, 0}, {0, 1, 0}, 60.0, 10.0, 5.0); }, "beyond the near plane");
    expectError([&] { Camera({0, 0, 0}, {0, 1, 0}, 60.0, {0, 10}, 1, 2); }, "viewport width");
}

TEST(SelectionValidation, NanEpsilonIsRefusedInsteadOfRefiningForever)
{
    const PatchQuadtree tree = flatTree();
    const Camera c = camera({1280, -500, 800}, {1280, 1280, 0});
    SelectionSettings s;
    s.max_patches = 8;
    s.epsilon_px = kNan;
    expectError([&] { tree.select(c, s); }, "epsilon_px is nan");
    s.epsilon_px = kInf;
    expectError([&] { tree.select(c, s); }, "epsilon_px is inf");
    s.epsilon_px = -1.0;
    expectError([&] { tree.select(c, s); }, "epsilon_px is -1");
    s.epsilon_px = 2.0;
    s.error_scale = kNan;
    expectError([&] { tree.select(c, s); }, "error_scale is nan");
    s.error_scale = 1.0;
    s.max_patches = 0;
    expectError([&] { tree.select(c, s); }, "max_patches");
    s.max_patches = 1;
    EXPECT_EQ(tree.select(c, s).patches.size(), 1u) << "ε is raised until the root alone fits";
}

TEST(CameraPathValidation, SpeedsFramesAndHeightsAreChecked)
{
    const TerrainFrame frame(PyramidGeometry(1001, 801, 33), 10.0, 10.0);
    const auto ground = [](double, double) { return 100.0; };
    CameraPathSettings s;
    s.speed_mps = kNan;
    expectError([&] { makeCameraPath(frame, 0, 500, ground, s, 3); }, "path speed_mps is nan");
    s.speed_mps = 0.0;
    expectError([&] { makeCameraPath(frame, 0, 500, ground, s, 3); }, "(0, 1e+06]");
    s = {};
    s.frame_seconds = kInf;
    expectError([&] { makeCameraPath(frame, 0, 500, ground, s, 3); }, "frame_seconds");
    s = {};
    s.height_above_ground = kNan;
    expectError([&] { makeCameraPath(frame, 0, 500, ground, s, 3); }, "height_above_ground");
    s = {};
    expectError([&] { makeCameraPath(frame, 0, 500, ground, s, -1); }, "path frames is -1");
    expectError([&] { makeCameraPath(frame, kNan, 500, ground, s, 3); }, "terrain height range");
    EXPECT_EQ(makeCameraPath(frame, 0, 500, ground, s, 0).size(), 0u);
}

TEST(CameraPathValidation, APathFileWithACoordinateBeyondTheRangeNamesItsLine)
{
    const std::string path = ::testing::TempDir() + "/ridge_path_huge.txt";
    std::ofstream(path) << "1 2 3 4 5 6\n1e300 2 3 4 5 6\n";
    const TerrainFrame frame(PyramidGeometry(1001, 801, 33), 10.0, 10.0);
    CameraPathSettings s;
    s.kind = path;
    expectError(
        [&] {
            makeCameraPath(
                frame, 0, 500, [](double, double) { return 0.0; }, s, 2);
        },
        path + ":2: every coordinate must be a number in [-1e+15, 1e+15]");
    std::remove(path.c_str());
}
