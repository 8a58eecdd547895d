#include "ridge/lod/horizon.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace ridge::lod {

HorizonOccluder::HorizonOccluder(const TerrainFrame& frame, glm::dvec3 camera, double min_height)
{
    if (!frame.onEllipsoid() || frame.geodetic().wrap_columns == 0 || !frame.poleRow(0.0) ||
        !frame.poleRow(double(frame.geometry().height() - 1)))
        return;
    // A metre inside, against rounding of the box corners.
    const double r = frame.geodetic().ellipsoid.b() + std::min(min_height, 0.0) - 1.0;
    const double d = glm::length(camera);
    if (!(r > 0.0) || !(d > r))
        return;
    active_ = true;
    camera_ = camera;
    direction_ = camera / d;
    plane_ = r * r / d;
    cos_alpha_ = std::sqrt(d * d - r * r) / d;
}

bool HorizonOccluder::hides(glm::dvec3 x) const
{
    if (!active_ || !(glm::dot(x, direction_) < plane_))
        return false;
    const glm::dvec3 v = x - camera_;
    return glm::dot(v, -direction_) >= glm::length(v) * cos_alpha_;
}

bool HorizonOccluder::hides(const Box& box) const
{
    if (!active_)
        return false;
    for (int k = 0; k < 8; ++k) {
        const glm::dvec3 corner((k & 1) ? box.max.x : box.min.x, (k & 2) ? box.max.y : box.min.y,
                                (k & 4) ? box.max.z : box.min.z);
        if (!hides(box.oriented ? box.origin + box.axes * corner : corner))
            return false;
    }
    return true;
}

} // namespace ridge::lod
