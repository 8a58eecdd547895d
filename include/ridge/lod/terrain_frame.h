#pragma once
// The terrain frame: the one place that maps a finest-grid sample (column, row) at a height to
// the world in which cameras are given, culling and error metrics are measured and positions
// are formed (relative to the camera) for the GPU. Two surfaces:
//
//   Plane      the archive's local metric frame (every archive before the globe):
//                x = column · spacing_x   metres east of the first column
//                y = (height − 1 − row) · spacing_y   metres north of the last (southern) row
//                z = metres, as decoded (offset + scale · code)
//              right-handed east-north-up, origin at the south-west corner at sea level;
//   Ellipsoid  Earth-centred, Earth-fixed metres on the reference ellipsoid (WGS 84), heights
//              along the ellipsoid's normal (lod/ellipsoid.h). Sample (c, r) lies either
//              at longitude λ0 + c·Δλ, latitude φ0 + r·Δφ (a north-up geographic grid:
//              GeodeticGrid; one whose columns span 360° wraps, rows at ±90° are the poles)
//              or where a projected CRS puts it (a ProjectedGrid: PROJ's map as a lattice).
//
// Doubles on the CPU: renderers subtract the camera position before converting to float
// (camera-relative rendering, no jitter far from the origin).
#include "ridge/lod/ellipsoid.h"
#include "ridge/lod/projected_grid.h"
#include "ridge/pyramid/pyramid_geometry.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <string_view>

namespace ridge::lod {

// A box: axis-aligned in the world (a plane frame's patches), or oriented (a globe's): then
// [min, max] is in the local frame `axes` (orthonormal columns) centred at `origin`, i.e. the
// world points origin + axes · q for q in [min, max].
struct Box {
    glm::dvec3 min{0.0};
    glm::dvec3 max{0.0};
    bool oriented = false;
    glm::dvec3 origin{0.0};
    glm::dmat3 axes{1.0};

    glm::dvec3 centre() const; // world
    // World point / direction in the box's own coordinates (the identity when axis-aligned).
    glm::dvec3 toLocal(glm::dvec3 world) const;
    glm::dvec3 directionToLocal(glm::dvec3 world) const;
};

enum class Surface { Plane, Ellipsoid };
// "plane", "ellipsoid".
std::string_view surfaceName(Surface s);

// Where the samples of a globe frame lie on the ellipsoid: a north-up geographic grid.
struct GeodeticGrid {
    double lon0 = 0.0, lat0 = 0.0; // radians, finest sample (0, 0)
    double dlon = 0.0;             // radians per column, > 0 (east)
    double dlat = 0.0;             // radians per row, < 0 (rows go south)
    // The grid's columns in 360° when they wrap around the Earth (column c and c + period are
    // the same meridian), else 0. Set only when the period is a whole number of columns.
    int64_t wrap_columns = 0;
    Ellipsoid ellipsoid;
};

class TerrainFrame {
  public:
    TerrainFrame() = default;
    // A plane frame.
    TerrainFrame(const PyramidGeometry& geometry, double spacing_x, double spacing_y)
        : geometry_(geometry), spacing_x_(spacing_x), spacing_y_(spacing_y)
    {
    }
    // A globe frame over `grid`; spacing_x/y are ground metres of a sample step at the grid's
    // centre (the archive header's), which the plane-metric coordinates (xOf, columnOf), the
    // texel criterion and extents use.
    static TerrainFrame ellipsoid(const PyramidGeometry& geometry, double spacing_x,
                                  double spacing_y, const GeodeticGrid& grid);
    // A globe frame over a projected raster's grid (shared: frames are copied freely).
    static TerrainFrame projected(const PyramidGeometry& geometry, double spacing_x,
                                  double spacing_y, std::shared_ptr<const ProjectedGrid> grid);

    const PyramidGeometry& geometry() const { return geometry_; }
    Surface surface() const { return surface_; }
    bool onEllipsoid() const { return surface_ == Surface::Ellipsoid; }
    // The ellipsoid, and on a geographic grid its longitudes and latitudes (a projected grid's
    // have lon0 = lat0 = dlon = dlat = 0 and never wrap).
    const GeodeticGrid& geodetic() const { return grid_; }
    // The projected raster's grid on a globe frame over one, else null.
    const ProjectedGrid* projectedGrid() const { return projected_.get(); }
    // Globe: upper bounds of the angle (radians, along the surface over its smallest radius of
    // curvature) one finest column and one row span anywhere: Δλ and |Δφ| on a geographic
    // grid. Sagitta, box and normal-turn bounds take them.
    double columnAngle() const;
    double rowAngle() const;
    double spacingX() const { return spacing_x_; }
    double spacingY() const { return spacing_y_; }

    // Plane-frame x, y of a finest-grid sample (column, row); fractional samples allowed.
    // On a globe they are the grid's metric coordinates (spacings at the largest scale), which
    // fog, extents and the legacy local point space still use.
    double xOf(double column) const { return column * spacing_x_; }
    double yOf(double row) const { return (geometry_.height() - 1 - row) * spacing_y_; }
    double columnOf(double x) const { return x / spacing_x_; }
    double rowOf(double y) const { return geometry_.height() - 1 - y / spacing_y_; }

    // Extent of the valid samples: [0, (width−1)·sx] x [0, (height−1)·sy].
    double extentX() const { return (geometry_.width() - 1) * spacing_x_; }
    double extentY() const { return (geometry_.height() - 1) * spacing_y_; }

    // Geographic globe: longitude, latitude (radians) of a column, row; latitudes are clamped to
    // ±π/2.
    double longitudeOf(double column) const { return grid_.lon0 + column * grid_.dlon; }
    double latitudeOf(double row) const;
    // Geographic globe: whether `row` lies on a pole (its latitude is ±90° to a millionth of a
    // row); false on any other frame (a pole inside a projected raster is an ordinary point).
    bool poleRow(double row) const;

    // The world point of sample (column, row) at `height` metres (drawn space: heights times
    // the exaggeration where the caller draws exaggerated), and the local up there (unit).
    glm::dvec3 worldOf(double column, double row, double height) const;
    glm::dvec3 upAt(double column, double row) const;
    // Local east, north, up at a sample (the plane's are the world axes).
    EnuBasis basisAt(double column, double row) const;
    // Inverse of worldOf: (column, row, height). Globe columns are taken in the period that
    // starts at column 0 − ½ (wrapping grids) or the nearest to the grid's centre.
    glm::dvec3 gridOf(glm::dvec3 world) const;
    // The height the GPU's heights are relative to for a camera at `world`: its z on a plane,
    // its height above the ellipsoid on a globe (so that heights near the camera are small).
    double referenceHeight(glm::dvec3 world) const { return gridOf(world).z; }
    // The local up through a world point: +z on a plane, the ellipsoid's normal on a globe
    // (what a camera there keeps upright).
    glm::dvec3 upThrough(glm::dvec3 world) const;

    // How far a straight cell `samples` finest samples a side may pass below the ellipsoid's
    // curved surface: the sagitta of its edges along the meridian and the parallel, summed,
    // each at most (a²/b)(1 − cos(θ/2)) for the edge's angle θ (≈ (a²/b)θ²/8), +1%; 0 on a
    // plane. A mesh drawn with cells that large is that much further from the surface than
    // its heights alone say, so the globe adds it to Err(P) (and the tessellator to Λ^(d)).
    double chordSag(double samples) const;
    // The same for one straight edge `samples` long along the grid's coarser axis: how far two
    // neighbours' borders drawn at different spacings may part (skirts).
    double edgeSag(double samples) const;

    // A conservative bound of patch `p` clipped to the valid extent, with heights
    // [min_z, max_z]: axis-aligned on a plane; on a globe oriented along the local axes at the
    // patch's centre and bounding the curved surface between its samples too.
    // The clip matters for culling and distances: the padding beyond the extent is not drawn.
    Box patchBox(PatchId p, double min_z, double max_z) const;

  private:
    Box ellipsoidPatchBox(PatchId p, double min_z, double max_z) const;

    PyramidGeometry geometry_;
    double spacing_x_ = 1.0;
    double spacing_y_ = 1.0;
    Surface surface_ = Surface::Plane;
    GeodeticGrid grid_;
    std::shared_ptr<const ProjectedGrid> projected_;
};

} // namespace ridge::lod
