// FlyCamera: the viewer's movement rules, without a window.
#include "ridge/render/fly_camera.h"

#include "ridge/lod/ellipsoid.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>

using ridge::render::FlyCamera;
using ridge::render::FlyInput;

namespace {

constexpr double kPi = 3.14159265358979323846;

double degrees(double radians)
{
    return radians * 180.0 / kPi;
}

void expectNear(glm::dvec3 a, glm::dvec3 b, double tolerance = 1e-9)
{
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

} // namespace

TEST(FlyCamera, MovingForwardForOneSecondAtTenMetresPerSecondCoversTenMetresAlongTheView)
{
    FlyCamera cam({100.0, 200.0, 300.0}, 0.3, -0.2, 10.0);
    const glm::dvec3 start = cam.position();
    const glm::dvec3 forward = cam.forward();
    FlyInput in;
    in.forward = true;
    cam.update(in, 1.0);
    expectNear(cam.position() - start, forward * 10.0);
    EXPECT_NEAR(glm::length(forward), 1.0, 1e-12);
}

TEST(FlyCamera, YawZeroLooksNorthAndNinetyDegreesLooksEast)
{
    expectNear(FlyCamera({0, 0, 0}, 0.0, 0.0, 1.0).forward(), {0.0, 1.0, 0.0});
    const FlyCamera east({0, 0, 0}, kPi / 2, 0.0, 1.0);
    expectNear(east.forward(), {1.0, 0.0, 0.0});
    // Strafing right while facing east heads south.
    expectNear(east.right(), {0.0, -1.0, 0.0});
    const ridge::lod::Camera c = east.camera({640, 360}, 60.0, 1.0, 1000.0);
    expectNear(c.forward(), {1.0, 0.0, 0.0});
    expectNear(c.right(), east.right());
}

TEST(FlyCamera, MouseMovesTurnRightAndLookDownAndPitchStopsShortOfVertical)
{
    FlyCamera cam({0, 0, 0}, 0.0, 0.0, 1.0);
    cam.setSensitivity(0.01);
    FlyInput in;
    in.mouse_dx = 10.0; // right
    in.mouse_dy = 10.0; // down
    cam.update(in, 0.0);
    EXPECT_NEAR(cam.yaw(), 0.1, 1e-12);
    EXPECT_NEAR(cam.pitch(), -0.1, 1e-12);

    in = FlyInput{};
    in.mouse_dy = -1e6; // far up
    cam.update(in, 0.0);
    EXPECT_NEAR(degrees(cam.pitch()), 89.0, 1e-9);
    in.mouse_dy = 1e6; // far down
    cam.update(in, 0.0);
    EXPECT_NEAR(degrees(cam.pitch()), -89.0, 1e-9);
    EXPECT_NEAR(degrees(FlyCamera({0, 0, 0}, 0.0, 2.0, 1.0).pitch()), 89.0, 1e-9);
    // Still a valid render camera at the limit.
    EXPECT_NO_THROW(cam.camera({640, 360}, 60.0, 1.0, 1000.0));
}

TEST(FlyCamera, FromACameraRoundTripsTheViewDirectionAndPosition)
{
    const ridge::lod::Viewport vp{800, 600};
    const glm::dvec3 position(1234.5, -678.25, 4321.0);
    const glm::dvec3 look_at(5000.0, 3000.0, 100.0); // north-east and below
    const ridge::lod::Camera original(position, look_at, 50.0, vp, 2.0, 1e5);
    const FlyCamera fly = FlyCamera::from(original);
    expectNear(fly.position(), position);
    expectNear(fly.forward(), original.forward(), 1e-12);
    const ridge::lod::Camera again = fly.camera(vp, 50.0, 2.0, 1e5);
    expectNear(again.forward(), original.forward(), 1e-12);
    expectNear(again.up(), original.up(), 1e-12);
    EXPECT_GT(fly.yaw(), 0.0);   // heading east of north
    EXPECT_LT(fly.pitch(), 0.0); // looking down
}

TEST(FlyCamera, SpeedScalesByTheFactorAndClampsToItsRange)
{
    FlyCamera cam({0, 0, 0}, 0.0, 0.0, 10.0);
    cam.scaleSpeed(1);
    EXPECT_NEAR(cam.speed(), 12.5, 1e-12);
    cam.scaleSpeed(-2);
    EXPECT_NEAR(cam.speed(), 8.0, 1e-12);
    cam.scaleSpeed(-1000);
    EXPECT_EQ(cam.speed(), FlyCamera::kMinSpeed);
    cam.scaleSpeed(1000);
    EXPECT_EQ(cam.speed(), FlyCamera::kMaxSpeed);
    cam.setSpeed(0.0);
    EXPECT_EQ(cam.speed(), FlyCamera::kMinSpeed);
    cam.setSpeed(1e9);
    EXPECT_EQ(cam.speed(), FlyCamera::kMaxSpeed);
    FlyInput in;
    in.speed_steps = -1000; // the mouse wheel goes through update()
    cam.update(in, 0.0);
    EXPECT_EQ(cam.speed(), FlyCamera::kMinSpeed);
}

TEST(FlyCamera, StrafingAndClimbingIgnorePitchAndDiagonalsKeepTheSpeed)
{
    FlyCamera cam({0, 0, 0}, 0.0, -0.7, 4.0); // looking north and down
    FlyInput in;
    in.right = true;
    cam.update(in, 0.5);
    expectNear(cam.position(), {2.0, 0.0, 0.0}); // east, no height change

    cam.setPosition({0, 0, 0});
    in = FlyInput{};
    in.up = true;
    in.fast = true;
    cam.update(in, 1.0);
    expectNear(cam.position(), {0.0, 0.0, 4.0 * FlyCamera::kFastFactor});

    cam.setPosition({0, 0, 0});
    in = FlyInput{};
    in.forward = true;
    in.left = true;
    cam.update(in, 1.0);
    EXPECT_NEAR(glm::length(cam.position()), 4.0, 1e-12);

    cam.setPosition({0, 0, 0});
    in = FlyInput{};
    in.forward = in.back = in.left = in.right = in.up = in.down = true; // all cancel
    cam.update(in, 1.0);
    expectNear(cam.position(), {0.0, 0.0, 0.0});
}

// On the globe the angles are local: yaw from true north, pitch above the local horizon,
// re-taken under the camera as it moves, and the camera upright to the local up.
TEST(FlyCamera, OnTheEllipsoidAnglesAreLocalAndLevelFlightFollowsTheCurve)
{
    const ridge::lod::Ellipsoid e;
    const double h0 = 1000.0;
    // Over the equator at the prime meridian, looking north along the ground.
    FlyCamera fly(ridge::lod::geodeticToEcef(e, 0.0, 0.0, h0), 0.0, 0.0, 1000.0);
    fly.followEllipsoid(e); // keeps the plane-style view (world +y: local east here)
    ASSERT_TRUE(fly.onEllipsoid());
    EXPECT_NEAR(degrees(fly.yaw()), 90.0, 1e-9);
    fly.update(FlyInput{.mouse_dx = -fly.yaw() / fly.sensitivity()}, 0.0); // turn to north
    expectNear(fly.forward(), {0.0, 0.0, 1.0}); // local north there is ECEF +z
    expectNear(fly.up(), {1.0, 0.0, 0.0});
    expectNear(fly.right(), {0.0, 1.0, 0.0}); // east: ECEF +y
    EXPECT_NEAR(fly.yaw(), 0.0, 1e-12);
    EXPECT_NEAR(fly.pitch(), 0.0, 1e-12);
    const ridge::lod::Camera cam = fly.camera({64, 64}, 60.0, 1.0, 1e7);
    expectNear(cam.worldUp(), fly.up());

    // 1,000 km north in 1 km steps: the camera stays level over the curve (a plane-style
    // straight line would climb 78 km), keeps heading north, and ends 9° further north.
    FlyInput forward;
    forward.forward = true;
    for (int i = 0; i < 1000; ++i)
        fly.update(forward, 1.0);
    const ridge::lod::Geodetic g = ridge::lod::ecefToGeodetic(e, fly.position());
    EXPECT_LT(std::abs(g.height - h0), 100.0) << "height after 1,000 km: " << g.height;
    EXPECT_NEAR(degrees(g.latitude), 9.04, 0.05);
    EXPECT_NEAR(degrees(g.longitude), 0.0, 1e-9);
    EXPECT_NEAR(fly.yaw(), 0.0, 1e-12);

    // Climbing goes along the local up: 500 m higher, same place.
    FlyInput climb;
    climb.up = true;
    fly.setSpeed(500.0);
    fly.update(climb, 1.0);
    const ridge::lod::Geodetic h = ridge::lod::ecefToGeodetic(e, fly.position());
    EXPECT_NEAR(h.height - g.height, 500.0, 1e-6);
    EXPECT_NEAR(h.latitude, g.latitude, 1e-12);

    // Turning right by a quarter turn faces local east.
    fly.update(FlyInput{.mouse_dx = (kPi / 2) / fly.sensitivity()}, 0.0);
    EXPECT_NEAR(degrees(fly.yaw()), 90.0, 1e-9);
    const glm::dvec3 east = glm::normalize(glm::cross(glm::dvec3(0, 0, 1), fly.up()));
    expectNear(fly.forward(), east, 1e-9);
}

// Following the ellipsoid keeps the view direction: yaw and pitch are re-expressed locally.
TEST(FlyCamera, FollowingTheEllipsoidKeepsTheViewDirection)
{
    const ridge::lod::Ellipsoid e;
    const glm::dvec3 p = ridge::lod::geodeticToEcef(e, 1.5, 0.7, 3000.0);
    const glm::dvec3 target = ridge::lod::geodeticToEcef(e, 1.52, 0.71, 0.0);
    const ridge::lod::Camera cam(p, target, 60.0, {64, 64}, 1.0, 1e7);
    FlyCamera fly = FlyCamera::from(cam);
    const glm::dvec3 before = fly.forward();
    fly.followEllipsoid(e);
    expectNear(fly.forward(), before, 1e-9);
    EXPECT_LT(fly.pitch(), 0.0) << "the target lies below the local horizon";
    EXPECT_GT(fly.yaw(), 0.0) << "and east of north";
}
