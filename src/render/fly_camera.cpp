#include "ridge/render/fly_camera.h"

#include "ridge/core/error.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace ridge::render {

namespace {
constexpr double kPi = 3.14159265358979323846;
} // namespace

FlyCamera::FlyCamera(glm::dvec3 position, double yaw, double pitch, double speed_mps)
{
    setPosition(position);
    setAngles(yaw, pitch);
    setSpeed(speed_mps);
}

FlyCamera FlyCamera::from(const lod::Camera& camera, double speed_mps)
{
    FlyCamera fly(camera.position(), 0.0, 0.0, speed_mps);
    fly.lookAlong(camera.forward());
    return fly;
}

void FlyCamera::followEllipsoid(const lod::Ellipsoid& ellipsoid)
{
    const glm::dvec3 f = forward();
    ellipsoid_ = ellipsoid;
    lookAlong(f);
}

glm::dmat3 FlyCamera::localBasis() const
{
    if (!ellipsoid_)
        return glm::dmat3(1.0);
    const lod::Geodetic g = lod::ecefToGeodetic(*ellipsoid_, position_);
    return lod::enuBasis(g.longitude, g.latitude).matrix();
}

void FlyCamera::lookAlong(glm::dvec3 world_direction)
{
    // Inverse of forward(): the heading from north towards east, the elevation above the
    // horizon (clamp guards asin against rounding just past ±1).
    const glm::dvec3 f = glm::normalize(glm::transpose(localBasis()) * world_direction);
    setAngles(std::atan2(f.x, f.y), std::asin(std::clamp(f.z, -1.0, 1.0)));
}

void FlyCamera::setAngles(double yaw, double pitch)
{
    checkParameter("fly camera yaw (radians)", yaw, ValueRange::any());
    checkParameter("fly camera pitch (radians)", pitch, ValueRange::any());
    // Wrapped so that yaw stays accurate however long the user spins.
    yaw_ = std::remainder(yaw, 2.0 * kPi);
    pitch_ = std::clamp(pitch, -kMaxPitch, kMaxPitch);
}

void FlyCamera::setPosition(glm::dvec3 position)
{
    checkParameters("fly camera position", &position.x, 3, lod::kCameraCoordinateRange);
    position_ = position;
}

void FlyCamera::setSpeed(double speed_mps)
{
    checkParameter("fly camera speed (m/s)", speed_mps, ValueRange::any());
    speed_ = std::clamp(speed_mps, kMinSpeed, kMaxSpeed);
}

void FlyCamera::scaleSpeed(double steps)
{
    checkParameter("fly camera speed steps", steps, ValueRange::any());
    // speed_ > 0 and the factor > 1, so the product is in [0, inf], never NaN: clamp it.
    speed_ = std::clamp(speed_ * std::pow(speed_factor_, steps), kMinSpeed, kMaxSpeed);
}

void FlyCamera::setSpeedFactor(double factor)
{
    checkParameter("fly camera speed factor", factor, kSpeedFactorRange);
    speed_factor_ = factor;
}

void FlyCamera::setSensitivity(double radians_per_pixel)
{
    checkParameter("fly camera sensitivity (radians per pixel)", radians_per_pixel,
                   kSensitivityRange);
    sensitivity_ = radians_per_pixel;
}

glm::dvec3 FlyCamera::forward() const
{
    const double c = std::cos(pitch_);
    return localBasis() * glm::dvec3(std::sin(yaw_) * c, std::cos(yaw_) * c, std::sin(pitch_));
}

glm::dvec3 FlyCamera::right() const
{
    // forward × up, normalised; independent of pitch, so strafing stays level.
    return localBasis() * glm::dvec3(std::cos(yaw_), -std::sin(yaw_), 0.0);
}

glm::dvec3 FlyCamera::up() const
{
    return localBasis()[2];
}

void FlyCamera::update(const FlyInput& in, double dt_seconds)
{
    const double numbers[4] = {in.mouse_dx, in.mouse_dy, in.speed_steps, dt_seconds};
    checkParameters("fly camera input (mouse dx, mouse dy, speed steps, dt)", numbers, 4,
                    ValueRange::any());
    setAngles(yaw_ + in.mouse_dx * sensitivity_, pitch_ - in.mouse_dy * sensitivity_);
    if (in.speed_steps != 0.0)
        scaleSpeed(in.speed_steps);

    const double dt = std::max(dt_seconds, 0.0);
    glm::dvec3 direction(0.0);
    direction += forward() * double(int(in.forward) - int(in.back));
    direction += right() * double(int(in.right) - int(in.left));
    direction += up() * double(int(in.up) - int(in.down));
    const double length = glm::length(direction);
    if (length < 1e-12 || dt == 0.0)
        return;
    const double speed = speed_ * (in.fast ? kFastFactor : 1.0);
    // A metre inside the camera range, so that camera()'s look-at point a metre ahead is too.
    const double limit = lod::kCameraCoordinateRange.hi - 1.0;
    // Capped so that a huge dt cannot make an infinite step (and inf · 0 = NaN components).
    // On a globe the angles are local: kept across the move, so that a level flight stays
    // level over the curve.
    position_ += direction / length * std::min(speed * dt, 4.0 * limit);
    position_ = glm::clamp(position_, glm::dvec3(-limit), glm::dvec3(limit));
}

lod::Camera FlyCamera::camera(lod::Viewport viewport, double fov_y_deg, double near_m,
                              double far_m) const
{
    // Camera wants a look-at point; one metre ahead keeps its subtraction exact enough at any
    // position a terrain reaches (|position| ≪ 2^52 m).
    return lod::Camera(position_, position_ + forward(), fov_y_deg, viewport, near_m, far_m, up());
}

} // namespace ridge::render
