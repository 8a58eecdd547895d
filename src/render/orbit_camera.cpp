#include "ridge/render/orbit_camera.h"

#include "ridge/core/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::render {

namespace {

constexpr double kPi = std::numbers::pi;

double wrapAngle(double a)
{
    a = std::remainder(a, 2.0 * kPi); // [−π, π]
    return a <= -kPi ? a + 2.0 * kPi : a;
}

void checkFinite(const char* name, double v)
{
    if (!std::isfinite(v))
        throw Error(std::string("orbit camera: ") + name + " is not finite");
}

// Where the ray from `origin` along `dir` (unit) first meets the ellipsoid raised by
// `height`, if it does: the ray scaled so that the ellipsoid becomes a sphere.
bool rayEllipsoid(const lod::Ellipsoid& e, double height, glm::dvec3 origin, glm::dvec3 dir,
                  glm::dvec3& hit)
{
    const double a = e.a + height, b = e.b() + height;
    if (!(a > 0.0 && b > 0.0))
        return false;
    const glm::dvec3 s(1.0 / a, 1.0 / a, 1.0 / b);
    const glm::dvec3 o = origin * s, d = dir * s;
    const double qa = glm::dot(d, d), qb = 2.0 * glm::dot(o, d), qc = glm::dot(o, o) - 1.0;
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc < 0.0)
        return false;
    const double t = (-qb - std::sqrt(disc)) / (2.0 * qa);
    if (!(t > 0.0))
        return false;
    hit = origin + t * dir;
    return true;
}

} // namespace

OrbitCamera::OrbitCamera(const lod::Ellipsoid& ellipsoid, double longitude, double latitude,
                         double target_height, double range, double heading, double tilt)
    : ellipsoid_(ellipsoid)
{
    for (const auto& [name, v] : {std::pair{"longitude", longitude},
                                  {"latitude", latitude},
                                  {"target height", target_height},
                                  {"range", range},
                                  {"heading", heading},
                                  {"tilt", tilt}})
        checkFinite(name, v);
    longitude_ = wrapAngle(longitude);
    latitude_ = std::clamp(latitude, -kMaxLatitude, kMaxLatitude);
    target_height_ = target_height;
    range_ = std::clamp(range, kMinRange, kMaxRange);
    heading_ = wrapAngle(heading);
    tilt_ = std::clamp(tilt, 0.0, kMaxTilt);
}

OrbitCamera OrbitCamera::around(const lod::Ellipsoid& e, const lod::Camera& camera,
                                double ground_height)
{
    const glm::dvec3 pos = camera.position();
    glm::dvec3 hit;
    if (!rayEllipsoid(e, ground_height, pos, camera.forward(), hit)) {
        // Looking past the Earth: straight down at the point under the camera.
        const lod::Geodetic g = lod::ecefToGeodetic(e, pos);
        return OrbitCamera(e, g.longitude, g.latitude, ground_height,
                           std::max(g.height - ground_height, kMinRange), 0.0, 0.0);
    }
    const lod::Geodetic t = lod::ecefToGeodetic(e, hit);
    const lod::EnuBasis b = lod::enuBasis(t.longitude, t.latitude);
    const glm::dvec3 back = pos - hit;
    const double range = glm::length(back);
    const glm::dvec3 u = back / std::max(range, 1e-9);
    const double up = glm::dot(u, b.up);
    const double tilt = std::acos(std::clamp(up, -1.0, 1.0));
    // The camera stands behind the target: its heading points from it to the target.
    const double heading = std::atan2(-glm::dot(u, b.east), -glm::dot(u, b.north));
    return OrbitCamera(e, t.longitude, t.latitude, t.height, range, tilt > 1e-6 ? heading : 0.0,
                       tilt);
}

void OrbitCamera::setTargetHeight(double metres)
{
    checkFinite("target height", metres);
    target_height_ = metres;
}

void OrbitCamera::update(const OrbitInput& in, lod::Viewport viewport, double fov_y_degrees,
                         double dt_seconds)
{
    for (const auto& [name, v] : {std::pair{"drag dx", in.drag_dx},
                                  {"drag dy", in.drag_dy},
                                  {"zoom steps", in.zoom_steps},
                                  {"turn", in.turn},
                                  {"tilt", in.tilt},
                                  {"dt", dt_seconds},
                                  {"field of view", fov_y_degrees}})
        checkFinite(name, v);
    const double dt = std::max(dt_seconds, 0.0);
    // Ground metres a pixel spans at the target, over the Earth's radius: the angle to move.
    const double fov = std::clamp(fov_y_degrees, 1.0, 179.0) * kPi / 180.0;
    const double pixel = 2.0 * std::tan(0.5 * fov) / std::max(viewport.height, 1);
    const double right = -in.drag_dx * pixel * range_, ahead = in.drag_dy * pixel * range_;
    const double ch = std::cos(heading_), sh = std::sin(heading_);
    const double east = right * ch + ahead * sh, north = -right * sh + ahead * ch;
    // Metres to angles through the ellipsoid's radii of curvature there: the meridian's M
    // and the prime vertical's N (the parallel's radius is N cos φ).
    const double e2 = ellipsoid_.e2(), s = std::sin(latitude_);
    const double w = 1.0 - e2 * s * s;
    const double n = ellipsoid_.a / std::sqrt(w) + target_height_;
    const double m = ellipsoid_.a * (1.0 - e2) / (w * std::sqrt(w)) + target_height_;
    const double parallel = n * std::max(std::cos(latitude_), 1e-6);
    latitude_ = std::clamp(latitude_ + north / m, -kMaxLatitude, kMaxLatitude);
    longitude_ = wrapAngle(longitude_ + east / parallel);
    range_ = std::clamp(range_ * std::pow(kZoomFactor, -in.zoom_steps), kMinRange, kMaxRange);
    heading_ = wrapAngle(heading_ + std::clamp(in.turn, -1.0, 1.0) * kTurnRate * dt);
    tilt_ = std::clamp(tilt_ + std::clamp(in.tilt, -1.0, 1.0) * kTurnRate * dt, 0.0, kMaxTilt);
}

glm::dvec3 OrbitCamera::target() const
{
    return lod::geodeticToEcef(ellipsoid_, longitude_, latitude_, target_height_);
}

glm::dvec3 OrbitCamera::back() const
{
    const lod::EnuBasis b = lod::enuBasis(longitude_, latitude_);
    const glm::dvec3 ahead = std::sin(heading_) * b.east + std::cos(heading_) * b.north;
    return std::cos(tilt_) * b.up - std::sin(tilt_) * ahead;
}

glm::dvec3 OrbitCamera::cameraUp() const
{
    // Perpendicular to the view: the heading's direction tipped up by the tilt, so that the
    // camera is never asked to keep upright to its own view direction (straight down).
    const lod::EnuBasis b = lod::enuBasis(longitude_, latitude_);
    const glm::dvec3 ahead = std::sin(heading_) * b.east + std::cos(heading_) * b.north;
    return glm::normalize(std::sin(tilt_) * b.up + std::cos(tilt_) * ahead);
}

glm::dvec3 OrbitCamera::position() const
{
    return target() + range_ * back();
}

lod::Camera OrbitCamera::camera(lod::Viewport viewport, double fov_y_degrees, double near_m,
                                double far_m) const
{
    return lod::Camera(position(), target(), fov_y_degrees, viewport, near_m, far_m, cameraUp());
}

} // namespace ridge::render
