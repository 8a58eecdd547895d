#pragma once
// A host application's camera (ridge::HostView) in ridge's terms, internal to src/api
// (GL-free): the LOD camera the renderer selects and tessellates for, the image's
// view-projection and depth convention, and the rays through the host's pixels for picking.
#include "ridge/ridge.h"

#include "ridge/lod/camera.h"
#include "ridge/render/terrain_renderer.h"

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace ridge::api {

// The rays through a viewport's pixels: eye space is the host's, world the local frame.
struct PixelRays {
    glm::dvec3 eye{0.0};            // local frame, metres
    glm::dmat3 world_from_eye{1.0}; // the view's rotation, inverted
    glm::dmat4 projection{1.0};     // eye → clip
    int width = 1, height = 1;      // pixels
    // The world direction (not normalised) of the ray from the eye through window point
    // (x, y): x right and y down from the top-left corner, pixels.
    glm::dvec3 direction(double x, double y) const;
};

struct HostCamera {
    // At the host's eye, looking along its −z, unrolled, with a symmetric frustum that
    // contains the host's and a viewport whose γ (pixels per unit of tangent) is at least the
    // host's largest: selection and tessellation meet ε in the host's pixels everywhere in
    // its frustum (conservatively: a rolled or off-centre frustum refines a little more).
    lod::Camera lod_camera;
    render::HostProjection projection;
    PixelRays rays;
};

// Checks `view` (finite, rigid, last row 0 0 0 1, within lod::kCameraCoordinateRange) and
// its projection (finite, perspective: last row 0 0 −1 0, an invertible x/y part, a depth
// direction that agrees with view.depth and a near plane in front of the eye); throws
// ridge::Error naming the field otherwise. `renderer` gives the far plane that holds the
// whole terrain.
HostCamera hostCamera(const HostView& view, const render::TerrainRenderer& renderer,
                      double exaggeration = 1.0);

// The HostView of ridge's own camera: view = rotation · translation(−position), projection
// render::reverseZProjection(camera), ReverseZ.
HostView hostViewOf(const lod::Camera& camera);

// Column-major arrays to and from glm.
glm::dmat4 matrixOf(const std::array<double, 16>& m);
std::array<double, 16> arrayOf(const glm::dmat4& m);

} // namespace ridge::api
