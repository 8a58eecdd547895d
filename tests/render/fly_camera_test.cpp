// FlyCamera: the viewer's movement rules, without a window.
#include "ridge/render/fly_camera.h"

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
