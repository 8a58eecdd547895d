#include "ridge/lod/camera_orientation.h"

#include "ridge/core/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::lod {

namespace {
constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;
}

glm::dvec3 headingPitchDirection(double heading_deg, double pitch_deg)
{
    checkParameter("heading (degrees)", heading_deg, kHeadingDegreesRange);
    checkParameter("pitch (degrees)", pitch_deg, kPitchDegreesRange);
    const double h = heading_deg * kRadiansPerDegree, p = pitch_deg * kRadiansPerDegree;
    const double c = std::cos(p);
    return {std::sin(h) * c, std::cos(h) * c, std::sin(p)};
}

HeadingPitch headingPitchOf(glm::dvec3 direction)
{
    checkParameters("view direction", &direction.x, 3, ValueRange::any());
    const double length = glm::length(direction);
    if (!(length > 0.0) || !std::isfinite(length))
        throw Error("view direction has no length: heading and pitch are undefined");
    const glm::dvec3 f = direction / length;
    return {std::atan2(f.x, f.y) / kRadiansPerDegree,
            std::asin(std::clamp(f.z, -1.0, 1.0)) / kRadiansPerDegree};
}

std::string renderCameraOptions(glm::dvec3 position, double heading_deg, double pitch_deg)
{
    // formatNumber: the shortest round-trip form, so the options read back bit-exact.
    return "--camera " + formatNumber(position.x) + "," + formatNumber(position.y) + "," +
           formatNumber(position.z) + " --heading " + formatNumber(heading_deg) + " --pitch " +
           formatNumber(pitch_deg);
}

} // namespace ridge::lod
