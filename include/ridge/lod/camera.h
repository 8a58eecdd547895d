#pragma once
// A perspective camera in the terrain frame, and the matrices renderers derive from it. Its
// "up" is the world's +z on a plane frame and the local up under the camera on a globe
// (TerrainFrame::upAt): the horizon stays level either way.
//
// Matrices are camera-relative: `view()` rotates only, so the world is translated by −position
// in double precision before anything becomes float. `viewProjection()` maps a
// camera-relative point (world − position) to clip space (OpenGL conventions, NDC z in [−1, 1]).
#include "ridge/core/parameter_check.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace ridge::lod {

// Terrain-frame coordinates of a camera position or look-at point, metres. 10^15 m (7000 AU)
// is far beyond any terrain and a double still resolves it to 1/8 m; beyond, positions and
// the differences renderers take lose whole metres, and soon overflow to infinity.
inline constexpr ValueRange kCameraCoordinateRange = ValueRange::closed(-1e15, 1e15);
// φ_v in degrees: a perspective projection needs (0, 180).
inline constexpr ValueRange kCameraFovYRange = {0.0, 180.0, true, true};
// Viewport sides, pixels: no GL implementation draws more than 65536 across.
inline constexpr int kMaxViewportPixels = 65536;

struct Viewport {
    int width = 1920;  // pixels, R_h
    int height = 1080; // pixels, R_v
};

class Camera {
  public:
    Camera() = default;
    // `fov_y_degrees` is the vertical field of view φ_v (kCameraFovYRange); φ_h follows from
    // the aspect ratio. near/far in metres, finite, 0 < near < far. `position` and `look_at`
    // within kCameraCoordinateRange and different; viewport sides in [1, kMaxViewportPixels].
    // Throws ridge::Error naming the parameter otherwise (NaN and infinities included): every
    // renderer, culling test and error metric downstream relies on a finite camera.
    // `world_up` is the direction the camera keeps upright (unit; the plane's +z by default).
    Camera(glm::dvec3 position, glm::dvec3 look_at, double fov_y_degrees, Viewport viewport,
           double near_m, double far_m, glm::dvec3 world_up = glm::dvec3(0.0, 0.0, 1.0));

    glm::dvec3 position() const { return position_; }
    glm::dvec3 forward() const { return forward_; }  // unit
    glm::dvec3 right() const { return right_; }      // unit
    glm::dvec3 up() const { return up_; }            // unit, completes the right-handed basis
    glm::dvec3 worldUp() const { return world_up_; } // unit, what the camera keeps upright
    Viewport viewport() const { return viewport_; }
    double fovY() const { return fov_y_; } // radians
    double fovX() const;                   // radians
    double nearPlane() const { return near_; }
    double farPlane() const { return far_; }

    glm::dmat4 view() const;       // rotation only (camera-relative)
    glm::dmat4 projection() const; // right-handed perspective, depth [−1, 1]
    glm::dmat4 viewProjection() const { return projection() * view(); }

    // Pixel position (x right, y down, origin top-left) and clip w of a world point.
    // Returns false when the point is behind the near plane.
    bool project(glm::dvec3 world, glm::dvec2& pixel) const;

  private:
    glm::dvec3 position_{0.0};
    glm::dvec3 forward_{0.0, 1.0, 0.0};
    glm::dvec3 right_{1.0, 0.0, 0.0};
    glm::dvec3 up_{0.0, 0.0, 1.0};
    glm::dvec3 world_up_{0.0, 0.0, 1.0};
    double fov_y_ = 1.0471975511965976; // 60°
    Viewport viewport_;
    double near_ = 1.0;
    double far_ = 1e6;
};

} // namespace ridge::lod
