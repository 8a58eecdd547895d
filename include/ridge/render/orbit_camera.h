#pragma once
// Orbiting a globe (`ridge view`'s orbit mode): the camera looks at a target point on the
// ellipsoid from `range` metres away, at a heading (from true north, clockwise) and a tilt
// (0: straight down, towards the horizon as it grows) in the target's local east, north, up.
// A drag turns the Earth under the cursor (the target moves by the ground a drag spans at the
// current range, the short way over the surface), the wheel and W/S zoom (the range scales,
// so that a notch is the same step from orbit and from a hill), A/D turn the heading and E/Q
// the tilt. Plain C++ (no GL, no window system): the viewer maps input to OrbitInput.
#include "ridge/core/parameter_check.h"
#include "ridge/lod/camera.h"
#include "ridge/lod/ellipsoid.h"

#include <glm/vec3.hpp>

namespace ridge::render {

// One frame's input. Drag deltas are pixels accumulated since the previous frame.
struct OrbitInput {
    double drag_dx = 0.0;    // + = right: the Earth follows the cursor (the target goes left)
    double drag_dy = 0.0;    // + = down (screen convention)
    double zoom_steps = 0.0; // + = closer: range /= kZoomFactor^steps (wheel notches, W/S)
    double turn = 0.0;       // −1..1: heading turns at kTurnRate (A/D)
    double tilt = 0.0;       // −1..1: tilt changes at kTurnRate (E/Q: towards the horizon)
};

class OrbitCamera {
  public:
    static constexpr double kMinRange = 10.0;                                 // m
    static constexpr double kMaxRange = 1.0e8;                                // m
    static constexpr double kMaxTilt = 85.0 * 3.14159265358979323846 / 180.0; // radians
    static constexpr double kMaxLatitude = 89.9 * 3.14159265358979323846 / 180.0;
    static constexpr double kZoomFactor = 1.25; // per step
    static constexpr double kTurnRate = 1.0;    // radians per second at full input

    OrbitCamera() = default;
    // Target at (longitude, latitude) radians, `target_height` metres above the ellipsoid;
    // range in [kMinRange, kMaxRange] (clamped), heading wrapped to (−π, π], tilt clamped to
    // [0, kMaxTilt], latitude to ±kMaxLatitude. Throws ridge::Error for non-finite arguments.
    OrbitCamera(const lod::Ellipsoid& ellipsoid, double longitude, double latitude,
                double target_height, double range, double heading, double tilt);
    // The orbit that shows what `camera` shows: its target where the view ray meets the
    // ellipsoid raised by `ground_height` (the point under the camera when it looks past the
    // Earth), the range, heading and tilt of the camera seen from there.
    static OrbitCamera around(const lod::Ellipsoid& ellipsoid, const lod::Camera& camera,
                              double ground_height);

    // Applies `in` for `dt_seconds` (≥ 0; negative is 0) with a view of `fov_y_degrees` over
    // `viewport` (the pixels a drag spans). Throws ridge::Error for non-finite input.
    void update(const OrbitInput& in, lod::Viewport viewport, double fov_y_degrees,
                double dt_seconds);

    // The render camera, looking at the target; near/far in metres, 0 < near < far.
    lod::Camera camera(lod::Viewport viewport, double fov_y_degrees, double near_m,
                       double far_m) const;
    glm::dvec3 position() const;
    glm::dvec3 target() const;

    double longitude() const { return longitude_; } // radians
    double latitude() const { return latitude_; }
    double targetHeight() const { return target_height_; }
    void setTargetHeight(double metres); // finite
    double range() const { return range_; }
    double heading() const { return heading_; }
    double tilt() const { return tilt_; }

  private:
    // The unit vector from the target to the camera, and the camera's up.
    glm::dvec3 back() const;
    glm::dvec3 cameraUp() const;

    lod::Ellipsoid ellipsoid_;
    double longitude_ = 0.0, latitude_ = 0.0, target_height_ = 0.0;
    double range_ = 1.0e7, heading_ = 0.0, tilt_ = 0.0;
};

} // namespace ridge::render
