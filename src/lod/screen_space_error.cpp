#include "ridge/lod/screen_space_error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ridge::lod {

double screenSpaceErrorFactor(const Camera& camera)
{
    const Viewport v = camera.viewport();
    const double h = v.width / std::tan(camera.fovX() * 0.5);
    const double w = v.height / std::tan(camera.fovY() * 0.5);
    return 0.5 * std::max(h, w);
}

double distanceToBox(glm::dvec3 c, const Box& box)
{
    const glm::dvec3 q = box.toLocal(c); // lengths are the same in the box's frame
    return glm::length(q - glm::clamp(q, box.min, box.max));
}

double visibleDepthBound(const Camera& camera, const Box& box, double rho, bool side_on)
{
    const double tx = std::tan(camera.fovX() * 0.5), ty = std::tan(camera.fovY() * 0.5);
    const double cos_max = 1.0 / std::sqrt(1.0 + tx * tx + ty * ty);
    // Nearest depth along the view axis: the box corner furthest against forward (n-vertex).
    const glm::dvec3 f = box.directionToLocal(camera.forward());
    const glm::dvec3 n(f.x >= 0 ? box.min.x : box.max.x, f.y >= 0 ? box.min.y : box.max.y,
                       f.z >= 0 ? box.min.z : box.max.z);
    const double w_min = glm::dot(n - box.toLocal(camera.position()), f);
    // r/w² <= 1/(cos θ_max · w) for a visible point (see the header): the extra cos θ_max
    // covers errors seen side-on near the screen's corners (1.09 ε without it).
    return (side_on ? cos_max : 1.0) * std::max(rho * cos_max, w_min);
}

double screen_space_error(double gamma, double err_metres, double rho)
{
    if (err_metres <= 0.0)
        return 0.0;
    if (rho <= 0.0)
        return std::numeric_limits<double>::infinity();
    return gamma * err_metres / rho;
}

double projectedSampleSpacing(double gamma, double spacing_metres, double rho)
{
    return screen_space_error(gamma, spacing_metres, rho);
}

} // namespace ridge::lod
