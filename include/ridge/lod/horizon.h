#pragma once
// Horizon culling on the globe: a patch whose every point lies behind the Earth, seen from the
// camera, is dropped with its subtree (the frustum keeps the far side of the globe in view
// from orbit: half of what it holds is hidden).
//
// The occluder is the sphere of radius b + the terrain's lowest height (inside the ellipsoid at
// that height everywhere, so solid wherever the terrain covers the Earth). From a camera C
// outside it, the rays that meet it fill the cone of half-angle α, sin α = R/|C|, and a point
// of that cone beyond the plane of the tangent circle (dot(X, Ĉ) < R²/|C|) lies behind the
// sphere. That region is convex, so a box whose eight corners are in it is hidden whole.
// Only for a frame that covers the whole Earth (wrapping columns, both poles): elsewhere there
// is no terrain where the sphere stands, and what lies behind it would be visible.
#include "ridge/lod/terrain_frame.h"

namespace ridge::lod {

class HorizonOccluder {
  public:
    // `min_height`: the terrain's lowest drawn height (metres, exaggerated where drawn so).
    // Inactive (hides nothing) on a plane, for a globe frame that does not cover the Earth,
    // or for a camera inside the sphere.
    HorizonOccluder(const TerrainFrame& frame, glm::dvec3 camera, double min_height);

    bool active() const { return active_; }
    bool hides(const Box& box) const;
    bool hides(glm::dvec3 point) const;

  private:
    bool active_ = false;
    glm::dvec3 camera_{0.0};
    glm::dvec3 direction_{0.0}; // Ĉ
    double plane_ = 0.0;        // R² / |C|
    double cos_alpha_ = 0.0;
};

} // namespace ridge::lod
