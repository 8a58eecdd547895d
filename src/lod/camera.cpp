#include "ridge/lod/camera.h"

#include "ridge/core/error.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace ridge::lod {

Camera::Camera(glm::dvec3 position, glm::dvec3 look_at, double fov_y_degrees, Viewport viewport,
               double near_m, double far_m, glm::dvec3 world_up)
    : position_(position), fov_y_(glm::radians(fov_y_degrees)), viewport_(viewport), near_(near_m),
      far_(far_m)
{
    checkParameters("camera position", &position.x, 3, kCameraCoordinateRange);
    checkParameters("camera look-at point", &look_at.x, 3, kCameraCoordinateRange);
    const glm::dvec3 dir = look_at - position;
    if (glm::length(dir) <= 0.0)
        throw Error("camera: the look-at point equals the camera position");
    checkParameter("camera field of view (degrees)", fov_y_degrees, kCameraFovYRange);
    checkParameter("viewport width", int64_t{viewport.width}, 1, kMaxViewportPixels);
    checkParameter("viewport height", int64_t{viewport.height}, 1, kMaxViewportPixels);
    checkParameter("camera near plane (m)", near_m, ValueRange::positive());
    checkParameter("camera far plane (m)", far_m, ValueRange::positive());
    if (!(far_m > near_m))
        throw Error("camera: the far plane (" + formatNumber(far_m) +
                    " m) must lie beyond the near plane (" + formatNumber(near_m) + " m)");
    checkParameters("camera world up", &world_up.x, 3, ValueRange::closed(-1.0, 1.0));
    if (std::abs(glm::length(world_up) - 1.0) > 1e-6)
        throw Error("camera: the world up direction must be a unit vector");
    world_up_ = world_up;
    forward_ = glm::normalize(dir);
    // Looking straight up or down: any right vector across the up direction will do.
    glm::dvec3 r = glm::cross(forward_, world_up);
    if (glm::length(r) < 1e-9) {
        r = glm::cross(glm::dvec3(0.0, 1.0, 0.0), world_up);
        if (glm::length(r) < 1e-9)
            r = glm::dvec3(1.0, 0.0, 0.0);
    }
    right_ = glm::normalize(r);
    up_ = glm::cross(right_, forward_);
}

double Camera::fovX() const
{
    const double aspect = double(viewport_.width) / viewport_.height;
    return 2.0 * std::atan(std::tan(fov_y_ * 0.5) * aspect);
}

glm::dmat4 Camera::view() const
{
    return glm::lookAtRH(glm::dvec3(0.0), forward_, up_);
}

glm::dmat4 Camera::projection() const
{
    const double aspect = double(viewport_.width) / viewport_.height;
    return glm::perspectiveRH_NO(fov_y_, aspect, near_, far_);
}

bool Camera::project(glm::dvec3 world, glm::dvec2& pixel) const
{
    const glm::dvec4 clip = viewProjection() * glm::dvec4(world - position_, 1.0);
    if (clip.w <= near_ * 0.5)
        return false;
    pixel.x = (clip.x / clip.w * 0.5 + 0.5) * viewport_.width;
    pixel.y = (0.5 - clip.y / clip.w * 0.5) * viewport_.height;
    return true;
}

} // namespace ridge::lod
