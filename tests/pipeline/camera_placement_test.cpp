// resolveCameraPlacement: geographic cameras land where GDAL's geotransform puts them, heights
// absolute or above the ground, and every conflicting combination is refused.
#include "test_support.h"

#include "ridge/core/error.h"
#include "ridge/lod/camera_orientation.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/camera_placement.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace ridge;

namespace {

std::string everest(const test::ScratchDir& dir, const std::string& source)
{
    BuildOptions o;
    o.patch_size = 33;
    const std::string path = dir.path("a.ridge");
    buildArchive(test::dataPath(source), path, o);
    return path;
}

} // namespace

TEST(CameraPlacement, TheEverestSummitByLonLatLandsOnItsColumnAndRow)
{
    test::ScratchDir dir;
    HeightQuery query(everest(dir, "everest_crop.tif"));
    const archive::Header& h = query.reader().header();
    // 86.925 E is pixel 210.5 (column 210) of a grid starting at 86.7495833 with 3" pixels;
    // 27.988 N is line 14.9 (row 14.4): y = (203 − 1 − 14.4)·spacing_y.
    CameraPlacement p;
    p.position_lonlat = glm::dvec3(86.925, 27.988, 9000.0);
    p.look_at_lonlat = glm::dvec3(86.85, 27.9, NAN);
    const ResolvedCamera c = resolveCameraPlacement(query, p);
    ASSERT_TRUE(c.position && c.look_at);
    EXPECT_NEAR(c.position->x, 210.0 * h.spacing_x, 1e-3);
    EXPECT_NEAR(c.position->y, (202.0 - 14.4) * h.spacing_y, 1e-3);
    EXPECT_EQ(c.position->z, 9000.0); // absolute
    // The look-at point without a height is on the ground.
    const double ground = query.sample({c.look_at->x, c.look_at->y}, PointSpace::Local).height;
    EXPECT_EQ(c.look_at->z, ground);

    p.above_ground = true;
    p.position_lonlat->z = 500.0;
    const ResolvedCamera above = resolveCameraPlacement(query, p);
    const double summit = query.sample({86.925, 27.988}, PointSpace::LonLat).height;
    EXPECT_GT(summit, 8700.0);
    EXPECT_NEAR(above.position->z, summit + 500.0, 1e-9);
}

TEST(CameraPlacement, OnAProjectedArchiveHeadingStaysGridNorth)
{
    test::ScratchDir dir;
    HeightQuery query(everest(dir, "everest_utm45.tif"));
    CameraPlacement p;
    p.position_lonlat = glm::dvec3(86.925, 27.95, 9000.0);
    p.heading_deg = 0.0;
    p.pitch_deg = -30.0;
    const ResolvedCamera c = resolveCameraPlacement(query, p);
    const glm::dvec3 d = *c.look_at - *c.position;
    EXPECT_NEAR(d.x, 0.0, 1e-9); // grid north: along +y, whatever the convergence
    EXPECT_GT(d.y, 0.0);
    const double convergence =
        query.georeference().convergenceDegrees({c.position->x, c.position->y});
    EXPECT_GT(convergence, 0.02); // west of 87° E: true north is clockwise of grid north
}

TEST(CameraPlacement, ConflictsAndGapsAreRefused)
{
    test::ScratchDir dir;
    HeightQuery query(everest(dir, "everest_crop.tif"));
    auto refused = [&](CameraPlacement p) {
        EXPECT_THROW(resolveCameraPlacement(query, p), Error);
    };
    CameraPlacement both;
    both.position = glm::dvec3(1, 2, 3);
    both.position_lonlat = glm::dvec3(86.9, 27.9, 100);
    refused(both);
    CameraPlacement look_and_heading;
    look_and_heading.position = glm::dvec3(1, 2, 3);
    look_and_heading.look_at = glm::dvec3(4, 5, 6);
    look_and_heading.heading_deg = 10;
    look_and_heading.pitch_deg = 0;
    refused(look_and_heading);
    CameraPlacement heading_only;
    heading_only.position = glm::dvec3(1, 2, 3);
    heading_only.heading_deg = 10;
    refused(heading_only);
    CameraPlacement no_position;
    no_position.heading_deg = 10;
    no_position.pitch_deg = 0;
    refused(no_position);
    CameraPlacement off;
    off.position_lonlat = glm::dvec3(80.0, 27.9, 100);
    off.above_ground = true;
    refused(off); // no ground there
    CameraPlacement bad;
    bad.position_lonlat = glm::dvec3(86.9, 91.0, 100);
    refused(bad);
    CameraPlacement nan;
    nan.position_lonlat = glm::dvec3(86.9, 27.9, NAN);
    refused(nan);
    CameraPlacement steep;
    steep.position = glm::dvec3(1, 2, 3);
    steep.heading_deg = 0;
    steep.pitch_deg = 90;
    refused(steep);
}
