// CoarseTerrain: ground heights, clip planes and the default camera from the level-0 patch,
// GL-free, for any x, y a caller can pass (NaN, infinities, the largest doubles).
#include "ridge/lod/coarse_terrain.h"

#include "ridge/core/error.h"

#include "error_expectations.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <random>

using namespace ridge;
using namespace ridge::lod;

namespace {

using ridge::test::errorOf;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// 65 x 49 samples at 10 m, patches of 33 (2 levels: the root's samples are 2 finest apart).
// Root codes form the plane 3i + 5j (i east, j south in root samples), which bilinear
// interpolation reproduces exactly; metres = 100 + 0.5 · code.
CoarseTerrain planeTerrain()
{
    const PyramidGeometry g(65, 49, 33);
    const int n = g.patchSize();
    std::vector<uint16_t> codes(size_t(n) * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            codes[size_t(j) * n + i] = uint16_t(3 * i + 5 * j);
    const TerrainFrame frame(g, 10.0, 10.0);
    HeightQuantization q;
    q.scale = 0.5;
    q.offset = 100.0;
    const Box box = frame.patchBox(PatchId{0, 0, 0}, 100.f, 100.f + 0.5f * (3 * 32 + 5 * 32));
    return CoarseTerrain(frame, box, std::move(codes), q);
}

// The plane in metres at terrain-frame (x, y), root samples clamped to the patch.
double planeAt(const CoarseTerrain& t, double x, double y)
{
    const double step = double(t.frame().geometry().step(0));
    const double i = std::clamp(t.frame().columnOf(x) / step, 0.0, 32.0);
    const double j = std::clamp(t.frame().rowOf(y) / step, 0.0, 32.0);
    return 100.0 + 0.5 * (3 * i + 5 * j);
}

} // namespace

TEST(CoarseTerrain, GroundHeightIsTheLevel0PatchBilinearly)
{
    const CoarseTerrain t = planeTerrain();
    for (const auto& [x, y] : {std::pair{0.0, 0.0}, {640.0, 480.0}, {123.4, 56.7}, {333.3, 10.0}})
        EXPECT_NEAR(t.groundHeight(x, y), planeAt(t, x, y), 1e-9) << x << ", " << y;
}

TEST(CoarseTerrain, NanOrInfiniteCoordinatesThrowAClearError)
{
    const CoarseTerrain t = planeTerrain();
    for (const auto& [x, y] : {std::pair{kNan, 0.0}, {0.0, kNan}, {kInf, 0.0}, {0.0, -kInf}}) {
        const std::string message = errorOf([&] { t.groundHeight(x, y); });
        EXPECT_NE(message.find("ground point (x, y) is ("), std::string::npos) << message;
        EXPECT_NE(message.find("finite"), std::string::npos) << message;
    }
}

TEST(CoarseTerrain, HugeFiniteCoordinatesClampToTheBorder)
{
    const CoarseTerrain t = planeTerrain();
    // South-west corner (x 0, y 0) is root sample (0, 32); north-east (extent) is (32, 0).
    EXPECT_DOUBLE_EQ(t.groundHeight(-DBL_MAX, -DBL_MAX), 100.0 + 0.5 * 5 * 32);
    EXPECT_DOUBLE_EQ(t.groundHeight(DBL_MAX, DBL_MAX), 100.0 + 0.5 * 3 * 32);
    EXPECT_DOUBLE_EQ(t.groundHeight(1e300, -1e300), 100.0 + 0.5 * (3 * 32 + 5 * 32));
    // The south-west sample itself: root column 0, row 24 (the last valid one).
    EXPECT_DOUBLE_EQ(t.groundHeight(-DBL_MIN, 1e-300), 100.0 + 0.5 * 5 * 24);
}

TEST(CoarseTerrain, AnyBitPatternEitherThrowsOrGivesAHeightOfThePatch)
{
    // A fuzz over raw doubles: NaNs of every payload, infinities, subnormals, huge values.
    const CoarseTerrain t = planeTerrain();
    std::mt19937_64 rng(7);
    const double lo = 100.0, hi = 100.0 + 0.5 * (3 * 32 + 5 * 32);
    for (int k = 0; k < 20000; ++k) {
        uint64_t bits[2] = {rng(), rng()};
        double xy[2];
        std::memcpy(xy, bits, sizeof xy);
        if (k % 3 == 0) // and plenty of ordinary coordinates
            xy[0] = std::ldexp(double(int64_t(bits[0]) >> 11), -40);
        if (std::isfinite(xy[0]) && std::isfinite(xy[1])) {
            const double h = t.groundHeight(xy[0], xy[1]);
            EXPECT_TRUE(h >= lo && h <= hi) << xy[0] << ", " << xy[1] << " -> " << h;
        } else {
            EXPECT_THROW(t.groundHeight(xy[0], xy[1]), Error) << xy[0] << ", " << xy[1];
        }
    }
}

TEST(CoarseTerrain, ClipPlanesSuitAnyFinitePositionAndRefuseNaN)
{
    const CoarseTerrain t = planeTerrain();
    for (const glm::dvec3 p : {glm::dvec3(300, 200, 500), glm::dvec3(1e14, -1e14, 1e15),
                               glm::dvec3(-1e15, 1e15, -1e15), glm::dvec3(320, 240, 150)}) {
        double near_m = 0, far_m = 0;
        t.clipPlanesFor(p, near_m, far_m);
        EXPECT_TRUE(std::isfinite(near_m) && std::isfinite(far_m));
        EXPECT_GE(near_m, 0.05);
        EXPECT_GT(far_m, near_m);
        EXPECT_NO_THROW(Camera(p, glm::dvec3(320, 240, 100), 60, {64, 64}, near_m, far_m));
    }
    double near_m = 0, far_m = 0;
    for (const glm::dvec3 p :
         {glm::dvec3(kNan, 0, 0), glm::dvec3(0, 0, kInf), glm::dvec3(0, 1e16, 0)}) {
        const std::string message = errorOf([&] { t.clipPlanesFor(p, near_m, far_m); });
        EXPECT_NE(message.find("camera position"), std::string::npos) << message;
    }
}

TEST(CoarseTerrain, TheDefaultCameraFramesTheWholeTerrain)
{
    const CoarseTerrain t = planeTerrain();
    const Camera c = t.defaultCamera({320, 200});
    const Box& b = t.box();
    for (int k = 0; k < 8; ++k) {
        const glm::dvec3 corner((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
                                (k & 4) ? b.max.z : b.min.z);
        glm::dvec2 px;
        ASSERT_TRUE(c.project(corner, px));
        EXPECT_GE(px.x, 0.0);
        EXPECT_LE(px.x, 320.0);
        EXPECT_GE(px.y, 0.0);
        EXPECT_LE(px.y, 200.0);
    }
    EXPECT_THROW(t.defaultCamera({320, 200}, kNan), Error);
    EXPECT_THROW(t.defaultCamera({0, 200}), Error);
}

TEST(CoarseTerrain, RefusesCodesThatAreNotOnePatch)
{
    const PyramidGeometry g(65, 49, 33);
    EXPECT_THROW(CoarseTerrain(TerrainFrame(g, 10, 10), Box{}, std::vector<uint16_t>(100), {}),
                 Error);
    EXPECT_THROW(CoarseTerrain(TerrainFrame(g, 0.0, 10), Box{}, std::vector<uint16_t>(33 * 33), {}),
                 Error);
}
