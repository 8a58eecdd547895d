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
        const std::string message = errorOf([&, x = x, y = y] { t.groundHeight(x, y); });
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

namespace {

// A mountain in Everest's proportions: 257 x 193 samples at 90 m (23 x 17 km), patches of 65
// (root samples 4 finest apart), a valley floor at 3400 m and a summit of 8800 m north-east of
// the centre: the relief is a quarter of the extent, as in tests/data/everest_crop.tif, whose
// default view (tests/apps) left the terrain a fifth of the frame.
CoarseTerrain mountainTerrain()
{
    const PyramidGeometry g(257, 193, 65);
    const TerrainFrame frame(g, 90.0, 90.0);
    const int n = g.patchSize();
    const double step = double(g.step(0));
    std::vector<uint16_t> codes(size_t(n) * n);
    uint16_t lo = UINT16_MAX, hi = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = frame.xOf(std::min(i * step, 256.0));
            const double y = frame.yOf(std::min(j * step, 192.0));
            const double d2 = (x - 15000) * (x - 15000) + (y - 11000) * (y - 11000);
            const uint16_t h =
                uint16_t(std::lround(3400 + 5400 * std::exp(-d2 / (2 * 4000.0 * 4000.0))));
            codes[size_t(j) * n + i] = h;
            lo = std::min(lo, h);
            hi = std::max(hi, h);
        }
    const Box box = frame.patchBox(PatchId{0, 0, 0}, lo, hi);
    return CoarseTerrain(frame, box, std::move(codes), HeightQuantization{});
}

// The level-0 surface over the terrain's extent: every root sample inside it and its last
// column and row (computed here, not taken from the class under test).
std::vector<glm::dvec3> surfaceOf(const CoarseTerrain& t)
{
    const PyramidGeometry& g = t.frame().geometry();
    std::vector<glm::dvec3> points;
    const int64_t step = g.step(0);
    for (int64_t r = 0;; r = std::min(r + step, int64_t(g.height() - 1))) {
        for (int64_t c = 0;; c = std::min(c + step, int64_t(g.width() - 1))) {
            const double x = t.frame().xOf(double(c)), y = t.frame().yOf(double(r));
            points.emplace_back(x, y, t.groundHeight(x, y));
            if (c == g.width() - 1)
                break;
        }
        if (r == g.height() - 1)
            break;
    }
    return points;
}

// The share of the picture the surface covers: its triangles (two per cell of `points`, a
// row-major grid `columns` wide) rasterised at the pixel centres.
double frameShare(const Camera& c, const std::vector<glm::dvec3>& points, size_t columns)
{
    const int w = c.viewport().width, h = c.viewport().height;
    std::vector<uint8_t> covered(size_t(w) * h, 0);
    auto fill = [&](glm::dvec2 a, glm::dvec2 b, glm::dvec2 d) {
        const double area = (b.x - a.x) * (d.y - a.y) - (d.x - a.x) * (b.y - a.y);
        if (area == 0)
            return;
        const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, d.x}))));
        const int x1 = std::min(w - 1, int(std::ceil(std::max({a.x, b.x, d.x}))));
        const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, d.y}))));
        const int y1 = std::min(h - 1, int(std::ceil(std::max({a.y, b.y, d.y}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const glm::dvec2 p(x + 0.5, y + 0.5);
                const double u = ((b.x - p.x) * (d.y - p.y) - (d.x - p.x) * (b.y - p.y)) / area;
                const double v = ((d.x - p.x) * (a.y - p.y) - (a.x - p.x) * (d.y - p.y)) / area;
                if (u >= 0 && v >= 0 && u + v <= 1)
                    covered[size_t(y) * w + x] = 1;
            }
    };
    const size_t rows = points.size() / columns;
    std::vector<glm::dvec2> px(points.size());
    for (size_t k = 0; k < points.size(); ++k)
        if (!c.project(points[k], px[k]))
            return 0.0; // a sample behind the camera: not framed
    for (size_t r = 0; r + 1 < rows; ++r)
        for (size_t col = 0; col + 1 < columns; ++col) {
            const size_t k = r * columns + col;
            fill(px[k], px[k + 1], px[k + columns]);
            fill(px[k + 1], px[k + columns + 1], px[k + columns]);
        }
    return double(std::count(covered.begin(), covered.end(), 1)) / double(covered.size());
}

size_t surfaceColumns(const CoarseTerrain& t)
{
    const PyramidGeometry& g = t.frame().geometry();
    return size_t((g.width() - 1 + g.step(0) - 1) / g.step(0)) + 1;
}

} // namespace

TEST(CoarseTerrain, TheDefaultCameraFramesTheWholeSurface)
{
    for (const CoarseTerrain& t : {planeTerrain(), mountainTerrain()})
        for (const Viewport vp : {Viewport{320, 200}, Viewport{640, 360}, Viewport{200, 400}}) {
            const Camera c = t.defaultCamera(vp);
            // Every sample of the surface inside the picture, with the 4 % margin.
            double lo_x = vp.width, hi_x = 0, lo_y = vp.height, hi_y = 0;
            for (const glm::dvec3& p : surfaceOf(t)) {
                glm::dvec2 px;
                ASSERT_TRUE(c.project(p, px));
                lo_x = std::min(lo_x, px.x);
                hi_x = std::max(hi_x, px.x);
                lo_y = std::min(lo_y, px.y);
                hi_y = std::max(hi_y, px.y);
            }
            EXPECT_GE(lo_x, 0.04 * vp.width - 0.01);
            EXPECT_LE(hi_x, 0.96 * vp.width + 0.01);
            EXPECT_GE(lo_y, 0.04 * vp.height - 0.01);
            EXPECT_LE(hi_y, 0.96 * vp.height + 0.01);
            // As close as that allows: the surface spans the margins on one axis, and is
            // centred on both (within a pixel: perspective centres the planes, not the pixels).
            const bool spans_x = lo_x < 0.04 * vp.width + 1 && hi_x > 0.96 * vp.width - 1;
            const bool spans_y = lo_y < 0.04 * vp.height + 1 && hi_y > 0.96 * vp.height - 1;
            EXPECT_TRUE(spans_x || spans_y)
                << lo_x << ".." << hi_x << " x " << lo_y << ".." << hi_y;
            EXPECT_NEAR(lo_x + hi_x, vp.width, 0.1 * vp.width);
            EXPECT_NEAR(lo_y + hi_y, vp.height, 0.1 * vp.height);
        }
    const CoarseTerrain t = planeTerrain();
    EXPECT_THROW(t.defaultCamera({320, 200}, kNan), Error);
    EXPECT_THROW(t.defaultCamera({0, 200}), Error);
}

// The default view of a mountain: the terrain's share of the frame, measured by rasterising
// its surface. Framing the bounding box (a summit 5 km above the valleys makes it tall and
// mostly empty) left it 18 % of a 640 x 360 frame and 23 % of 320 x 240; framing the surface,
// 37 % and 32 %.
TEST(CoarseTerrain, TheDefaultCameraFillsTheFrameWithTheTerrain)
{
    const CoarseTerrain t = mountainTerrain();
    const std::vector<glm::dvec3> surface = surfaceOf(t);
    const size_t columns = surfaceColumns(t);
    ASSERT_EQ(surface.size() % columns, 0u);
    for (const Viewport vp : {Viewport{640, 360}, Viewport{320, 240}}) {
        const double share = frameShare(t.defaultCamera(vp), surface, columns);
        EXPECT_GE(share, 0.30) << vp.width << "x" << vp.height;
    }
}

TEST(CoarseTerrain, RefusesCodesThatAreNotOnePatch)
{
    const PyramidGeometry g(65, 49, 33);
    EXPECT_THROW(CoarseTerrain(TerrainFrame(g, 10, 10), Box{}, std::vector<uint16_t>(100), {}),
                 Error);
    EXPECT_THROW(CoarseTerrain(TerrainFrame(g, 0.0, 10), Box{}, std::vector<uint16_t>(33 * 33), {}),
                 Error);
}
