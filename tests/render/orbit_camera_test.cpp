// The viewer's orbit mode (render/orbit_camera.h), GL-free: the camera looks at its target
// from its range; a drag moves the ground under the cursor by what the drag spans there,
// whatever the range and heading; the wheel scales the range and keeps the target; the
// orbit made from a camera shows what that camera shows; the poles and hostile input stay
// finite or are refused.
#include "error_expectations.h"

#include "ridge/render/orbit_camera.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace ridge::render {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const lod::Viewport kView{800, 600};

TEST(OrbitCamera, LooksAtItsTargetFromItsRangeAtItsHeadingAndTilt)
{
    const lod::Ellipsoid e;
    const OrbitCamera o(e, 86.9 * kDeg, 27.99 * kDeg, 8000.0, 20000.0, 30.0 * kDeg, 60.0 * kDeg);
    const lod::Camera c = o.camera(kView, 60.0, 1.0, 1e6);
    EXPECT_NEAR(glm::length(c.position() - o.target()), 20000.0, 1e-6);
    EXPECT_GT(glm::dot(c.forward(), glm::normalize(o.target() - c.position())), 1.0 - 1e-12);
    // 60° from straight down, looking towards heading 30° (north-north-east).
    const lod::EnuBasis b = lod::enuBasis(86.9 * kDeg, 27.99 * kDeg);
    EXPECT_NEAR(std::acos(-glm::dot(c.forward(), b.up)) / kDeg, 60.0, 1e-9);
    EXPECT_NEAR(std::atan2(glm::dot(c.forward(), b.east), glm::dot(c.forward(), b.north)) / kDeg,
                30.0, 1e-9);
    // Upright: the camera's up leans towards the local up.
    EXPECT_GT(glm::dot(c.up(), b.up), 0.4);
    // Straight down is a valid view too (its up is the heading's direction).
    const OrbitCamera down(e, 0.0, 0.0, 0.0, 1e7, 0.0, 0.0);
    const lod::Camera d = down.camera(kView, 60.0, 1.0, 1e8);
    EXPECT_NEAR(glm::dot(d.forward(), glm::dvec3(-1.0, 0.0, 0.0)), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(d.up(), glm::dvec3(0.0, 0.0, 1.0)), 1.0, 1e-12); // north up
}

TEST(OrbitCamera, ADragMovesTheGroundUnderTheCursorByWhatItSpans)
{
    const lod::Ellipsoid e;
    for (const double heading : {0.0, 90.0, -135.0})
        for (const double range : {2000.0, 2.0e5}) {
            OrbitCamera o(e, 10.0 * kDeg, 45.0 * kDeg, 0.0, range, heading * kDeg, 0.0);
            const glm::dvec3 before = o.target();
            const lod::Camera c0 = o.camera(kView, 60.0, 1.0, 1e8);
            // Dragging 100 px to the right: the target moves to the camera's left by the
            // ground 100 px spanned, so the point that was under the cursor follows it.
            OrbitInput in;
            in.drag_dx = 100.0;
            o.update(in, kView, 60.0, 0.0);
            const glm::dvec3 moved = o.target() - before;
            const double spans = 100.0 * 2.0 * std::tan(30.0 * kDeg) / kView.height * range;
            EXPECT_NEAR(glm::length(moved), spans, 3e-3 * spans) << heading << "°, " << range;
            EXPECT_LT(glm::dot(glm::normalize(moved), c0.right()), -0.999) << heading;
        }
}

TEST(OrbitCamera, ZoomScalesTheRangeAndKeepsTheTarget)
{
    const lod::Ellipsoid e;
    OrbitCamera o(e, 1.0, 0.5, 100.0, 1.0e6, 0.3, 0.4);
    const glm::dvec3 target = o.target();
    OrbitInput in;
    in.zoom_steps = 2.0;
    o.update(in, kView, 60.0, 0.016);
    EXPECT_NEAR(o.range(), 1.0e6 / (1.25 * 1.25), 1e-6);
    EXPECT_LT(glm::length(o.target() - target), 1e-9);
    in.zoom_steps = 1000.0; // clamped, never through the target
    o.update(in, kView, 60.0, 0.016);
    EXPECT_EQ(o.range(), OrbitCamera::kMinRange);
    in.zoom_steps = -1000.0;
    o.update(in, kView, 60.0, 0.016);
    EXPECT_EQ(o.range(), OrbitCamera::kMaxRange);
    // Keys turn the heading and tilt at their rate, the tilt within [0, kMaxTilt].
    in = {};
    in.turn = 1.0;
    in.tilt = 1.0;
    o.update(in, kView, 60.0, 0.5);
    EXPECT_NEAR(o.heading(), 0.3 + 0.5 * OrbitCamera::kTurnRate, 1e-12);
    EXPECT_NEAR(o.tilt(), 0.4 + 0.5 * OrbitCamera::kTurnRate, 1e-12);
    o.update(in, kView, 60.0, 10.0);
    EXPECT_EQ(o.tilt(), OrbitCamera::kMaxTilt);
}

TEST(OrbitCamera, TheOrbitAroundACameraShowsWhatItShows)
{
    const lod::Ellipsoid e;
    const glm::dvec3 pos = lod::geodeticToEcef(e, 7.0 * kDeg, 46.0 * kDeg, 3000.0);
    const glm::dvec3 at = lod::geodeticToEcef(e, 7.1 * kDeg, 46.1 * kDeg, 500.0);
    const lod::Camera c(pos, at, 60.0, kView, 1.0, 1e6, lod::geodeticUp(7.0 * kDeg, 46.0 * kDeg));
    const OrbitCamera o = OrbitCamera::around(e, c, 500.0);
    EXPECT_LT(glm::length(o.position() - pos), 1e-3);
    EXPECT_LT(glm::length(o.target() - at), 1.0); // the ray meets the raised ellipsoid there
    const lod::Camera back = o.camera(kView, 60.0, 1.0, 1e6);
    EXPECT_GT(glm::dot(back.forward(), c.forward()), 1.0 - 1e-9);
    // Looking past the Earth: straight down at the point under the camera.
    const lod::Camera sky(pos, pos + lod::geodeticUp(7.0 * kDeg, 46.0 * kDeg), 60.0, kView, 1.0,
                          1e6, glm::dvec3(0.0, 0.0, 1.0));
    const OrbitCamera up = OrbitCamera::around(e, sky, 0.0);
    EXPECT_NEAR(up.range(), 3000.0, 1e-3);
    EXPECT_EQ(up.tilt(), 0.0);
}

TEST(OrbitCamera, ThePolesAndHostileInputStayFiniteOrAreRefused)
{
    const lod::Ellipsoid e;
    OrbitCamera o(e, 0.0, 89.0 * kDeg, 0.0, 1.0e5, 0.0, 0.0);
    OrbitInput in;
    in.drag_dy = 1.0e6; // far past the pole: the latitude stops short of it
    o.update(in, kView, 60.0, 0.016);
    EXPECT_LE(o.latitude(), OrbitCamera::kMaxLatitude);
    const lod::Camera c = o.camera(kView, 60.0, 1.0, 1e8);
    EXPECT_TRUE(std::isfinite(c.position().x) && std::isfinite(c.forward().z));
    in = {};
    in.drag_dx = NAN;
    test::expectError([&] { o.update(in, kView, 60.0, 0.016); }, "drag dx");
    test::expectError([&] { OrbitCamera(e, 0.0, 0.0, 0.0, INFINITY, 0.0, 0.0); }, "range");
}

} // namespace
} // namespace ridge::render
