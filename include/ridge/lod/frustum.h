#pragma once
// View-frustum culling of patch bounding boxes with the n/p-vertex test.
//
// Six planes are extracted from the view-projection matrix (Gribb & Hartmann). For each plane
// the box corner furthest along the plane normal (the p-vertex) decides "outside" and the
// nearest (the n-vertex) decides "inside"; two dot products per plane, no corner loop.
#include "ridge/lod/camera.h"
#include "ridge/lod/terrain_frame.h"

#include <glm/vec4.hpp>

namespace ridge::lod {

enum class Visibility { Outside, Intersecting, Inside };

class Frustum {
  public:
    Frustum() = default;
    // Planes of `camera`, in the terrain frame (not camera-relative).
    explicit Frustum(const Camera& camera);

    Visibility classify(const Box& box) const;
    // Planes as (n, d) with n·x + d >= 0 inside; n is unit length.
    const glm::dvec4& plane(int i) const { return planes_[i]; }

  private:
    glm::dvec4 planes_[6];
};

} // namespace ridge::lod
