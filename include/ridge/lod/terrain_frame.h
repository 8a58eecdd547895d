#pragma once
// The archive's local metric frame, in which cameras are given and patches are placed.
//
//   x = column · spacing_x                 metres east of the first column
//   y = (height − 1 − row) · spacing_y     metres north of the last (southern) row
//   z = metres                              elevation, as decoded (offset + scale · code)
//
// A right-handed east-north-up frame whose origin is the south-west corner sample at sea
// level, so that every valid sample has x, y >= 0. Doubles on the CPU: renderers subtract the
// camera position before converting to float (camera-relative rendering, no jitter far from
// the origin).
#include "ridge/pyramid/pyramid_geometry.h"

#include <glm/vec3.hpp>

namespace ridge::lod {

// An axis-aligned box in the terrain frame.
struct Box {
    glm::dvec3 min{0.0};
    glm::dvec3 max{0.0};
    glm::dvec3 centre() const { return (min + max) * 0.5; }
};

class TerrainFrame {
  public:
    TerrainFrame() = default;
    TerrainFrame(const PyramidGeometry& geometry, double spacing_x, double spacing_y)
        : geometry_(geometry), spacing_x_(spacing_x), spacing_y_(spacing_y)
    {
    }

    const PyramidGeometry& geometry() const { return geometry_; }
    double spacingX() const { return spacing_x_; }
    double spacingY() const { return spacing_y_; }

    // Terrain frame x, y of a finest-grid sample (column, row); fractional samples allowed.
    double xOf(double column) const { return column * spacing_x_; }
    double yOf(double row) const { return (geometry_.height() - 1 - row) * spacing_y_; }
    double columnOf(double x) const { return x / spacing_x_; }
    double rowOf(double y) const { return geometry_.height() - 1 - y / spacing_y_; }

    // Extent of the valid samples: [0, (width−1)·sx] x [0, (height−1)·sy].
    double extentX() const { return (geometry_.width() - 1) * spacing_x_; }
    double extentY() const { return (geometry_.height() - 1) * spacing_y_; }

    // Footprint of patch `p` clipped to the valid extent, with heights [min_z, max_z].
    // The clip matters for culling and distances: the padding beyond the extent is not drawn.
    Box patchBox(PatchId p, double min_z, double max_z) const;

  private:
    PyramidGeometry geometry_;
    double spacing_x_ = 1.0;
    double spacing_y_ = 1.0;
};

} // namespace ridge::lod
