#pragma once
// A projected raster's samples on the ellipsoid (a UTM DEM on the globe, in its place).
//
// PROJ maps a projected CRS's x, y to longitude and latitude exactly, but neither the GPU nor
// a per-vertex CPU loop can call it. The terrain frame carries instead
//
//   S(c, r)   the ellipsoid point (height 0, Earth-centred, Earth-fixed metres) under finest
//             sample (c, r)
//
// as a bicubic Hermite surface over a lattice of nodes every `step` samples, whose values and
// first and cross derivatives PROJ gave (lod/archive_frame.cpp). The lattice is refined until
// the surface is within a tolerance (a millimetre) of PROJ's points between its nodes, and
// the shaders evaluate the same surface relative to a node near the camera
// (terrain_common.glsl, projectedOffset). S is interpolated in ECEF, not in longitude and
// latitude: it stays smooth through a pole inside the raster (polar stereographic) and across
// the antimeridian. A sample at height h lies at S + h·n(S), n the ellipsoid's normal there.
#include "ridge/lod/ellipsoid.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <functional>
#include <optional>
#include <vector>

namespace ridge::lod {

// S and its derivatives per finest sample at one lattice node.
struct LatticeNode {
    glm::dvec3 s{0.0};    // S
    glm::dvec3 s_c{0.0};  // ∂S/∂c
    glm::dvec3 s_r{0.0};  // ∂S/∂r
    glm::dvec3 s_cr{0.0}; // ∂²S/∂c∂r
};

// The extent a lattice must cover and how exact it must be.
struct LatticeRequest {
    // Columns [0, columns_end] and rows [0, rows_end]: where vertices may be placed (the
    // pyramid's padded extent). The lattice starts one node before 0.
    double columns_end = 0.0, rows_end = 0.0;
    // The raster's last sample: PROJ must place every node up to one node beyond it, and the
    // surface is held to `tolerance` metres of PROJ inside it.
    double last_column = 0.0, last_row = 0.0;
    double tolerance = 1e-3;
    // The coarsest node spacing tried (samples, a power of two); halved until `tolerance`
    // holds or a side reaches `max_nodes`.
    int max_nodes = 257;
};

class ProjectedGrid {
  public:
    // Longitude, latitude (radians, WGS 84) of finest sample (c, r) (fractions allowed), or
    // nullopt where the projection has no point.
    using ToGeodetic = std::function<std::optional<std::array<double, 2>>(double c, double r)>;

    ProjectedGrid() = default;
    // Samples `to_geodetic` on nodes and between them. Throws ridge::Error when a node within
    // one node of the raster has no point (a projection that does not reach the raster);
    // nodes beyond that without one continue their nearest neighbour's tangent plane (only
    // clipped vertices reach them).
    static ProjectedGrid build(const Ellipsoid& ellipsoid, const LatticeRequest& request,
                               const ToGeodetic& to_geodetic);

    const Ellipsoid& ellipsoid() const { return ellipsoid_; }
    int step() const { return step_; } // samples between nodes, a power of two
    int nodesX() const { return nodes_x_; }
    int nodesY() const { return nodes_y_; }
    int firstColumn() const { return -step_; } // column, row of node (0, 0)
    int firstRow() const { return -step_; }
    const LatticeNode& node(int i, int j) const { return nodes_[size_t(j) * nodes_x_ + i]; }
    // The largest distance, metres, between the surface and PROJ's points that the build
    // measured (cell centres and edge midpoints inside the raster).
    double measuredError() const { return measured_error_; }
    // Upper bounds of the ground metres per finest column and per row anywhere in the raster
    // (+1%), which the sagitta and box bounds take.
    double columnMetresBound() const { return column_metres_; }
    double rowMetresBound() const { return row_metres_; }

    // S at (c, r); beyond the lattice the nearest cell's cubic continues.
    glm::dvec3 surfaceAt(double c, double r) const;
    // ∂S/∂c and ∂S/∂r at (c, r).
    void tangentsAt(double c, double r, glm::dvec3& s_c, glm::dvec3& s_r) const;
    // The ellipsoid's outward unit normal through a point near it (the geodetic up).
    glm::dvec3 normalThrough(glm::dvec3 point) const;
    // The (c, r) whose S is nearest the foot of `point` on the ellipsoid: Gauss–Newton from the
    // nearest of a coarse set of nodes, clamped to the lattice (a point whose foot is off it
    // gets the lattice's edge).
    glm::dvec2 gridOf(glm::dvec3 point) const;

  private:
    // The cell holding (c, r), clamped to the lattice, and the fractions in it.
    void locate(double c, double r, int& i, int& j, double& u, double& v) const;

    Ellipsoid ellipsoid_;
    int step_ = 1;
    int nodes_x_ = 0, nodes_y_ = 0;
    std::vector<LatticeNode> nodes_;
    double measured_error_ = 0.0;
    double column_metres_ = 0.0, row_metres_ = 0.0;
};

// The Hermite basis of one cubic on [0, 1]: weights of the values at 0 and 1 and of the
// derivatives (times the cell's length) there; `derivative` gives their d/du instead.
std::array<double, 4> hermiteWeights(double u, bool derivative = false);

} // namespace ridge::lod
