#pragma once
// A free-flying first-person camera for the interactive viewer (`ridge view`): position, yaw,
// pitch and speed, advanced by one frame's input. Plain C++ (no GL, no window system), so the
// movement rules are unit-testable; the app maps keys and mouse to FlyInput.
//
// Terrain frame (ridge/lod/camera.h): x east, y north, z up, metres. Yaw is the compass
// heading in radians: 0 looks north (+y), +π/2 looks east (+x). Pitch is the angle above the
// horizon in radians, kept within ±kMaxPitch so the view never becomes vertical (the camera's
// right vector is derived from forward × z, which degenerates there).
//
// On a globe (followEllipsoid) the same angles are taken in the local east, north, up under
// the camera, recomputed as it moves: yaw from true north, pitch above the local horizon,
// strafing level, E and Q along the local up, and the camera kept upright to that up. Flying
// "straight" then follows the Earth's curve at a constant heading, as an aircraft does.
#include "ridge/lod/camera.h"
#include "ridge/lod/ellipsoid.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <optional>

namespace ridge::render {

// One frame's input. Key states are "held during the frame"; mouse deltas are accumulated
// since the previous frame.
struct FlyInput {
    bool forward = false;     // along the view direction (W)
    bool back = false;        // (S)
    bool left = false;        // horizontally, perpendicular to the view (A)
    bool right = false;       // (D)
    bool up = false;          // along +z (E)
    bool down = false;        // along −z (Q)
    bool fast = false;        // moves kFastFactor times faster while held (Shift)
    double mouse_dx = 0.0;    // pixels, + = right: turns right (yaw grows)
    double mouse_dy = 0.0;    // pixels, + = down (screen convention): looks down
    double speed_steps = 0.0; // speed *= speedFactor()^steps (mouse-wheel notches, keys)
};

class FlyCamera {
  public:
    static constexpr double kMinSpeed = 0.1;                                   // m/s
    static constexpr double kMaxSpeed = 1e6;                                   // m/s
    static constexpr double kMaxPitch = 89.0 * 3.14159265358979323846 / 180.0; // radians
    static constexpr double kFastFactor = 5.0;
    // speedFactor() per step, and radians of turn per pixel: beyond, one wheel notch or one
    // pixel throws the camera around.
    static constexpr ValueRange kSpeedFactorRange = {1.0, 100.0, true, false};
    static constexpr ValueRange kSensitivityRange = ValueRange::openClosed(0.0, 1.0);

    FlyCamera() = default;
    // Angles in radians (pitch is clamped to ±kMaxPitch, yaw wrapped to (−π, π]); speed in m/s
    // (clamped to [kMinSpeed, kMaxSpeed]); position within lod::kCameraCoordinateRange.
    // Throws ridge::Error for NaN or infinite arguments (they would poison every later pose),
    // as do all setters and update().
    FlyCamera(glm::dvec3 position, double yaw, double pitch, double speed_mps);

    // Starts where `camera` is, looking where it looks (pitch clamped), at `speed_mps`.
    static FlyCamera from(const lod::Camera& camera, double speed_mps = 100.0);

    // From now on, angles and moves are in the local frame of `ellipsoid` under the camera
    // (ECEF positions); the view direction is kept (yaw and pitch re-expressed locally).
    void followEllipsoid(const lod::Ellipsoid& ellipsoid);
    bool onEllipsoid() const { return ellipsoid_.has_value(); }
    // Local east, north, up at the camera (the world axes on a plane).
    glm::dmat3 localBasis() const;

    // Applies mouse look (mouse deltas × sensitivity), then speed steps, then moves for
    // `dt_seconds` (≥ 0; negative is treated as 0). Opposing keys cancel; a diagonal moves at
    // the same speed as a straight line. The caller bounds dt if a stalled frame should not
    // jump the camera. The position stays a metre inside lod::kCameraCoordinateRange
    // (clamped), so that camera() always works.
    void update(const FlyInput& in, double dt_seconds);

    // The render camera at the current pose; near/far in metres, 0 < near < far.
    lod::Camera camera(lod::Viewport viewport, double fov_y_deg, double near_m, double far_m) const;

    // Unit view direction, the unit horizontal vector to its right (forward × up) and the
    // local up, in the world.
    glm::dvec3 forward() const;
    glm::dvec3 right() const;
    glm::dvec3 up() const;

    glm::dvec3 position() const { return position_; }
    void setPosition(glm::dvec3 position);  // within lod::kCameraCoordinateRange
    double yaw() const { return yaw_; }     // radians
    double pitch() const { return pitch_; } // radians
    double speed() const { return speed_; } // m/s
    void setSpeed(double speed_mps);        // finite; clamped to [kMinSpeed, kMaxSpeed]
    // Multiplies the speed by speedFactor()^steps (negative steps slow down), clamped.
    void scaleSpeed(double steps);
    double speedFactor() const { return speed_factor_; }
    void setSpeedFactor(double factor); // kSpeedFactorRange
    // Radians of turn per pixel of mouse movement.
    double sensitivity() const { return sensitivity_; }
    void setSensitivity(double radians_per_pixel); // kSensitivityRange

  private:
    void setAngles(double yaw, double pitch);

    // Yaw and pitch from a world direction in the local basis at the current position.
    void lookAlong(glm::dvec3 world_direction);

    glm::dvec3 position_{0.0};
    std::optional<lod::Ellipsoid> ellipsoid_;
    double yaw_ = 0.0;
    double pitch_ = 0.0;
    double speed_ = 100.0;
    double speed_factor_ = 1.25;
    double sensitivity_ = 0.0025; // ≈ 0.14° per pixel: a 1600 px sweep turns about 230°
};

} // namespace ridge::render
