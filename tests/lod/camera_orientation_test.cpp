// Heading/pitch ↔ direction, and the render command-line form of a camera.
#include "ridge/lod/camera_orientation.h"

#include "ridge/core/error.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

using namespace ridge;
using namespace ridge::lod;

TEST(CameraOrientation, HeadingIsClockwiseFromGridNorthAndPitchAboveTheHorizon)
{
    const glm::dvec3 north = headingPitchDirection(0, 0), east = headingPitchDirection(90, 0);
    EXPECT_NEAR(north.y, 1.0, 1e-15);
    EXPECT_NEAR(east.x, 1.0, 1e-15);
    EXPECT_NEAR(headingPitchDirection(180, 0).y, -1.0, 1e-15);
    const glm::dvec3 down = headingPitchDirection(30, -45);
    EXPECT_NEAR(down.z, -std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(glm::length(down), 1.0, 1e-15);
    for (double h : {-179.0, -90.0, 0.0, 45.5, 179.0})
        for (double p : {-89.0, -20.0, 0.0, 35.0, 89.0}) {
            const HeadingPitch back = headingPitchOf(headingPitchDirection(h, p) * 7.0);
            EXPECT_NEAR(back.heading_deg, h, 1e-12);
            EXPECT_NEAR(back.pitch_deg, p, 1e-12);
        }
    EXPECT_THROW(headingPitchDirection(NAN, 0), Error);
    EXPECT_THROW(headingPitchDirection(0, 90), Error);
    EXPECT_THROW(headingPitchDirection(400, 0), Error);
    EXPECT_THROW(headingPitchOf({0, 0, 0}), Error);
}

TEST(CameraOrientation, RenderOptionsReadBackToTheSameDoubles)
{
    const glm::dvec3 position(17226.682934073848, 0.1 + 0.2, -3.5e-7);
    const double heading = 200.0 / 3.0, pitch = -20.123456789012345;
    const std::string text = renderCameraOptions(position, heading, pitch);
    char x[64], y[64], z[64], h[64], p[64];
    ASSERT_EQ(std::sscanf(text.c_str(), "--camera %63[^,],%63[^,],%63s --heading %63s --pitch %63s",
                          x, y, z, h, p),
              5)
        << text;
    EXPECT_EQ(std::strtod(x, nullptr), position.x);
    EXPECT_EQ(std::strtod(y, nullptr), position.y);
    EXPECT_EQ(std::strtod(z, nullptr), position.z);
    EXPECT_EQ(std::strtod(h, nullptr), heading);
    EXPECT_EQ(std::strtod(p, nullptr), pitch);
}
