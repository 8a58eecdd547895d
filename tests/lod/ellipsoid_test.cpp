// The globe's geometry in double (lod/ellipsoid.h, lod/terrain_frame.h): ECEF against known
// WGS 84 values, the inverse to the micrometre from the ground to orbit, the GPU's offset
// algebra against plain differences, and oriented patch boxes that hold every point of their
// patch — samples, the curved surface between them, the poles and the wrap included.
#include "ridge/lod/ellipsoid.h"
#include "ridge/lod/frustum.h"
#include "ridge/lod/horizon.h"
#include "ridge/lod/screen_space_error.h"
#include "ridge/lod/terrain_frame.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace ridge::lod {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(Ellipsoid, EcefOfKnownPointsIsExact)
{
    const Ellipsoid e = Ellipsoid::wgs84();
    const glm::dvec3 equator = geodeticToEcef(e, 0.0, 0.0, 0.0);
    EXPECT_DOUBLE_EQ(equator.x, 6378137.0);
    EXPECT_DOUBLE_EQ(equator.y, 0.0);
    const glm::dvec3 pole = geodeticToEcef(e, 1.234, std::numbers::pi / 2, 10.0);
    EXPECT_EQ(pole.x, 0.0); // exactly on the axis, whatever the longitude
    EXPECT_EQ(pole.y, 0.0);
    EXPECT_NEAR(pole.z, 6356752.314245 + 10.0, 1e-6);
    // 45°N 90°E, 1 km up: (N + h) cos φ and (N(1 − e²) + h) sin φ with N(45°) = 6388838.29 m.
    const glm::dvec3 p = geodeticToEcef(e, 90.0 * kDeg, 45.0 * kDeg, 1000.0);
    EXPECT_NEAR(p.x, 0.0, 1e-6);
    EXPECT_NEAR(p.y, 4518297.985630, 1e-5);
    EXPECT_NEAR(p.z, 4488055.515647, 1e-5);
}

TEST(Ellipsoid, GeodeticRoundTripsWithinAMicrometreFromTheSeaFloorToOrbit)
{
    const Ellipsoid e = Ellipsoid::wgs84();
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> lon(-180.0, 180.0), lat(-90.0, 90.0), h(-11000.0, 4e7);
    for (int i = 0; i < 20000; ++i) {
        const double l = lon(rng) * kDeg, f = lat(rng) * kDeg, z = i % 4 ? h(rng) : 0.5 * i;
        const glm::dvec3 p = geodeticToEcef(e, l, f, z);
        const Geodetic g = ecefToGeodetic(e, p);
        const glm::dvec3 back = geodeticToEcef(e, g.longitude, g.latitude, g.height);
        ASSERT_LT(glm::length(back - p), 1e-6) << l << " " << f << " " << z;
        ASSERT_NEAR(g.height, z, 1e-6);
    }
    // The centre of the Earth: a finite answer (the north pole, −b), no NaN.
    const Geodetic c = ecefToGeodetic(e, glm::dvec3(0.0));
    EXPECT_TRUE(std::isfinite(c.latitude) && std::isfinite(c.height));
}

TEST(Ellipsoid, OffsetAlgebraMatchesPlainDifferencesAtEveryScale)
{
    const Ellipsoid e = Ellipsoid::wgs84();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < 5000; ++i) {
        // Latitudes stay within ±90° (beyond, geodeticToEcef clamps onto the pole).
        const double la = 180.0 * u(rng) * kDeg, fa = 60.0 * u(rng) * kDeg, ha = 5000.0 * u(rng);
        const double scale = 0.5 * std::pow(10.0, -7.0 + 7.0 * (0.5 + 0.5 * u(rng))); // ≤ ½ rad
        const double dl = scale * u(rng), df = scale * u(rng), dh = 1000.0 * u(rng);
        const glm::dvec3 want =
            geodeticToEcef(e, la + dl, fa + df, ha + dh) - geodeticToEcef(e, la, fa, ha);
        const glm::dvec3 got = ellipsoidOffset(e, la, fa, ha, dl, df, dh);
        // Plain differences lose ~1e-9 m to cancellation at Earth scale.
        ASSERT_LT(glm::length(got - want), 1e-8 + 1e-12 * glm::length(want));
    }
}

// A whole-Earth grid of 2° samples (181 x 91, columns 0..360, rows 90..-90, wrapping) and a
// 3″ one near the pole.
TerrainFrame globe(int w, int h, double lon0, double lat0, double step_deg, int64_t wrap)
{
    GeodeticGrid g;
    g.lon0 = lon0 * kDeg;
    g.lat0 = lat0 * kDeg;
    g.dlon = step_deg * kDeg;
    g.dlat = -step_deg * kDeg;
    g.wrap_columns = wrap;
    return TerrainFrame::ellipsoid(PyramidGeometry(w, h, 17), 1.0, 1.0, g);
}

TEST(TerrainFrameEllipsoid, PatchBoxesHoldEveryPointOfTheirPatch)
{
    const TerrainFrame frames[] = {globe(181, 91, 0.0, 90.0, 2.0, 180),
                                   globe(301, 203, 0.0, 89.96, 3.0 / 3600.0, 0)};
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (const TerrainFrame& f : frames) {
        const PyramidGeometry& g = f.geometry();
        int boxes = 0;
        for (int level = 0; level <= g.finestLevel(); ++level)
            for (int y = 0; y < g.patchesY(level); ++y)
                for (int x = 0; x < g.patchesX(level); ++x) {
                    const PatchId p{level, x, y};
                    const double lo = -8000.0, hi = 6000.0;
                    const Box b = f.patchBox(p, lo, hi);
                    ASSERT_TRUE(b.oriented);
                    const double span = double(g.cells()) * g.step(level);
                    const double c0 = x * span, r0 = y * span;
                    const double c1 = std::min(c0 + span, double(g.width() - 1));
                    const double r1 = std::min(r0 + span, double(g.height() - 1));
                    // Random points of the patch (between samples too) at random heights.
                    for (int k = 0; k < 400; ++k) {
                        const double c = c0 + (c1 - c0) * u(rng), r = r0 + (r1 - r0) * u(rng);
                        const glm::dvec3 q = b.toLocal(f.worldOf(c, r, lo + (hi - lo) * u(rng)));
                        const double slack = 1e-6 * (1.0 + glm::length(q));
                        ASSERT_TRUE(glm::all(glm::greaterThanEqual(q, b.min - slack)) &&
                                    glm::all(glm::lessThanEqual(q, b.max + slack)))
                            << "level " << level << " patch " << x << "," << y << " point " << c
                            << "," << r;
                    }
                    ++boxes;
                }
        EXPECT_GT(boxes, 3);
    }
}

TEST(TerrainFrameEllipsoid, OrientedBoxesCullAndMeasureConservatively)
{
    const TerrainFrame f = globe(181, 91, 0.0, 90.0, 2.0, 180);
    const PatchId p{f.geometry().finestLevel(), 3, 2};
    const Box b = f.patchBox(p, -100.0, 3000.0);
    const double cm = p.x * 16 + 8, rm = p.y * 16 + 8;
    const glm::dvec3 centre = f.worldOf(cm, rm, 0.0), up = f.upAt(cm, rm);
    // A camera 500 km above the patch looking at it: inside the frustum; looking away: out.
    const glm::dvec3 pos = centre + 5e5 * up;
    const Camera looking(pos, centre, 60.0, {640, 480}, 10.0, 1e8, glm::dvec3(0, 0, 1));
    EXPECT_NE(Frustum(looking).classify(b), Visibility::Outside);
    const Camera away(pos, pos + up, 60.0, {640, 480}, 10.0, 1e8, glm::dvec3(0, 0, 1));
    EXPECT_EQ(Frustum(away).classify(b), Visibility::Outside);
    // ρ is at most the distance to any point of the patch.
    const double rho = distanceToBox(pos, b);
    for (int k = 0; k <= 16; ++k) {
        const double c = p.x * 16 + k, r = p.y * 16 + (16 - k);
        EXPECT_LE(rho, glm::length(f.worldOf(c, r, 0.0) - pos) + 1e-6);
    }
    // And not much less: the box reaches ~15 km above the surface (3 km, the sagitta of 5°).
    EXPECT_GT(rho, 4.5e5);
}

TEST(TerrainFrameEllipsoid, GridOfInvertsWorldOfAndWrapsTheColumns)
{
    const TerrainFrame f = globe(181, 91, 0.0, 90.0, 2.0, 180);
    for (double c : {0.0, 1.5, 89.0, 179.25})
        for (double r : {0.5, 45.0, 89.5}) {
            const glm::dvec3 g = f.gridOf(f.worldOf(c, r, 1234.5));
            EXPECT_NEAR(g.x, c, 1e-9);
            EXPECT_NEAR(g.y, r, 1e-9);
            EXPECT_NEAR(g.z, 1234.5, 1e-6);
        }
    // Column 180 is column 0 one turn on: the same point, the same grid position back.
    EXPECT_LT(glm::length(f.worldOf(180.0, 30.0, 0.0) - f.worldOf(0.0, 30.0, 0.0)), 1e-6);
    EXPECT_NEAR(f.gridOf(f.worldOf(180.0, 30.0, 0.0)).x, 0.0, 1e-9);
    // Every sample of a pole row is one point.
    EXPECT_EQ(f.worldOf(0.0, 0.0, 7.0), f.worldOf(77.0, 0.0, 7.0));
    EXPECT_EQ(f.worldOf(3.0, 90.0, 7.0), f.worldOf(140.0, 90.0, 7.0));
    EXPECT_TRUE(f.poleRow(0.0) && f.poleRow(90.0) && !f.poleRow(1.0));
}

TEST(HorizonOccluder, HidesOnlyWhatTheEarthHides)
{
    const TerrainFrame f = globe(181, 91, 0.0, 90.0, 2.0, 180);
    const Ellipsoid e = f.geodetic().ellipsoid;
    const glm::dvec3 camera(3.0 * e.a, 1e5, 2e5);
    const HorizonOccluder h(f, camera, -9000.0);
    ASSERT_TRUE(h.active());
    EXPECT_TRUE(h.hides(glm::dvec3(-e.a, 0.0, 0.0))); // the far side
    EXPECT_FALSE(h.hides(glm::dvec3(e.a, 0.0, 0.0))); // below the camera
    // Never a point whose segment to the camera misses the occluding sphere.
    const double r = e.b() - 9000.0 - 1.0;
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int hidden = 0;
    for (int i = 0; i < 100000; ++i) {
        const glm::dvec3 x = (e.b() - 9000.0 + 20000.0 * (0.5 + 0.5 * u(rng))) *
                             glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
        if (!h.hides(x))
            continue;
        ++hidden;
        const glm::dvec3 d = x - camera;
        const double t = std::clamp(-glm::dot(camera, d) / glm::dot(d, d), 0.0, 1.0);
        ASSERT_LT(glm::length(camera + t * d), r + 1e-6) << "a visible point was hidden";
    }
    EXPECT_GT(hidden, 30000); // about half of the shell
    // Boxes: a far-side patch goes, the one under the camera stays.
    const PyramidGeometry& g = f.geometry();
    const int L = g.finestLevel();
    EXPECT_TRUE(h.hides(f.patchBox({L, 5, 2}, -9000.0, 6000.0)));  // around 180°
    EXPECT_FALSE(h.hides(f.patchBox({L, 0, 2}, -9000.0, 6000.0))); // around 0°..32°
    // A plane, or a globe that does not cover the Earth, hides nothing.
    EXPECT_FALSE(HorizonOccluder(TerrainFrame(g, 1.0, 1.0), camera, 0.0).active());
    EXPECT_FALSE(
        HorizonOccluder(globe(301, 203, 0.0, 89.96, 3.0 / 3600.0, 0), camera, 0.0).active());
}

} // namespace
} // namespace ridge::lod
