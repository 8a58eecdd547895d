#pragma once
// Rays against the triangles a frame drew (render::TerrainRenderer::lastFrameSurface),
// internal to src/api (GL-free): what Renderer::pick intersects.
#include "ridge/render/terrain_renderer.h"

#include <glm/vec3.hpp>

#include <optional>
#include <vector>

namespace ridge::api {

struct SurfaceHit {
    double t = 0.0;           // along the ray: origin + t · direction
    glm::dvec3 relative{0.0}; // the hit, relative to the surface's camera position, metres
    PatchId patch;            // the drawn patch whose triangle was hit
    glm::dvec3 triangle[3];   // that triangle's corners, relative like `relative`
};

// A frame's triangles grouped by patch instance, each group with its bounding box, so that a
// ray tests only the triangles of the patches whose boxes it crosses. Skirt triangles (and
// the clipping walls) are left out: a pick finds the terrain's surface, not the strips that
// hide cracks below it.
class PickSurface {
  public:
    PickSurface() = default;
    explicit PickSurface(render::CapturedSurface surface);

    glm::dvec3 cameraPosition() const { return camera_position_; }
    // The first surface triangle the ray origin + t·direction (t > 0) meets, the origin given
    // relative to cameraPosition(); edges and vertices count as inside (a ray through a
    // shared vertex hits). Double precision over the triangles' float vertices.
    std::optional<SurfaceHit> intersect(glm::dvec3 origin, glm::dvec3 direction) const;

  private:
    glm::dvec3 camera_position_{0.0};
    std::vector<glm::dvec3> corners_; // 3 a surface triangle, grouped by instance
    struct Group {
        PatchId patch;
        size_t first = 0, count = 0; // triangles
        glm::dvec3 min{0.0}, max{0.0};
    };
    std::vector<Group> groups_;
};

} // namespace ridge::api
