#pragma once
// A view direction as heading and pitch, the way `ridge render --heading/--pitch`, the
// viewer's overlay and render::FlyCamera state it (plain C++, no GL):
//   heading  degrees clockwise from grid north, the terrain frame's +y (0 north, 90 east).
//            Grid north is the raster's "up": true north for a north-up lon/lat archive; in a
//            projected CRS it differs by the meridian convergence
//            (TerrainGeoreference::convergenceDegrees: up to a few degrees in a UTM zone).
//   pitch    degrees above the horizon (negative looks down), within ±kMaxPitchDegrees.
#include "ridge/core/parameter_check.h"

#include <glm/vec3.hpp>

#include <string>

namespace ridge::lod {

// The fly camera's limit: a vertical view has no right vector (forward × z degenerates).
inline constexpr double kMaxPitchDegrees = 89.0;
inline constexpr ValueRange kHeadingDegreesRange = ValueRange::closed(-360.0, 360.0);
inline constexpr ValueRange kPitchDegreesRange =
    ValueRange::closed(-kMaxPitchDegrees, kMaxPitchDegrees);

// Unit direction of heading/pitch: (sin h cos p, cos h cos p, sin p). Throws ridge::Error for
// values outside the ranges above (NaN and infinities included).
glm::dvec3 headingPitchDirection(double heading_deg, double pitch_deg);

struct HeadingPitch {
    double heading_deg = 0.0; // (−180, 180]
    double pitch_deg = 0.0;   // [−90, 90]
};
// The inverse for a non-zero direction (normalised first). Throws for a zero or non-finite one.
HeadingPitch headingPitchOf(glm::dvec3 direction);

// The camera as `ridge render` takes it: "--camera X,Y,Z --heading H --pitch P", each number in
// its shortest form that reads back to the same double, so that a printed camera renders the
// same view.
std::string renderCameraOptions(glm::dvec3 position, double heading_deg, double pitch_deg);

} // namespace ridge::lod
