#pragma once
// A quantized-mesh-1.0 tile of a geographic TMS tile made from the tile's height grid: the
// grid's error-bounded TIN (tin_mesh.h), with its edge lists for the client's skirts, its
// bounding volumes on WGS 84 and the vertex order the index coding needs.
//
// The grid is rectilinear and placed in the format's own coordinates: column c at u[c], row r
// at v[r], the first and last lines the tile's edges. A grid cut from an archive puts its
// inner lines on the archive's own samples (tile_sampler.h), so the bound holds at the data;
// a uniform grid (uniformTileHeights) is the special case. The TIN's geometry is the quantized
// geometry the client draws.
//
// Error: every grid sample lies within TerrainTile::error of the mesh the client draws — the
// TIN's bound plus half a height quantization step, (max − min) / 32767 / 2. (The grid's own
// distance from the terrain is the caller's to add: resampling, the archive's bound.)
//
// Curvature. A client draws each triangle flat in ECEF: a chord under the curved surface its
// vertices lie on, which sags L²/(8R) between vertices L apart — 2 cm at 1 km, 2 km across a
// zoom-0 tile's 4-vertex mesh, whose two triangles then cut through the Earth. So tiles are
// meshed and measured in g = h − q(u, v), q the drop of a sphere of radius 6,371 km below the
// plane tangent at the tile's centre (sphereDrop): linear interpolation of g is, to first
// order in the tile's angular size, the height the client draws (drawnHeightAt), and the TIN
// adds vertices wherever the chords would sag past the bound — flat ocean included. Along a
// shared edge q is the same function for both tiles, so neighbours still choose the same
// border vertices. Zooms 0 and 1 span angles where the paraboloid is only roughly the sphere
// (6.4·10⁶ m of drop against 7.9·10⁶ at 90°): their bound is approximate there.
//
// Shared edges: the TIN's border vertices depend on the border's samples and positions alone,
// so two tiles of a zoom that sample a shared edge alike (same lines along it, same heights)
// put the same vertices on it; their heights agree within each tile's half quantization step.
#include "ridge/web/quantized_mesh.h"
#include "ridge/web/tile_grid.h"

#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ridge::web {

struct TileHeights {
    TileKey key; // GeographicTms
    // The grid's lines in the format's coordinates: u of each column, west to east (0 first,
    // 32767 last, strictly increasing), v of each row, north to south (32767 first, 0 last,
    // strictly decreasing).
    std::vector<int32_t> u, v;
    // u.size() × v.size() heights above the ellipsoid, metres, finite; row-major from the
    // north-west corner.
    std::vector<float> heights;
};

// The lines of a uniform grid of `cells` cells a side (1..32767): line i at
// round(i · 32767 / cells), increasing.
std::vector<int32_t> uniformLines(int cells);
// A uniform grid's key and lines (heights left empty for the caller).
TileHeights uniformTileHeights(TileKey key, int cells);

// q(u, v) above, metres, for tile k (u, v in the format's units, fractional allowed).
double sphereDrop(TileKey k, double u, double v);
// Per vertex of `mesh` (tile k): its decoded height less sphereDrop there.
std::vector<double> flattenedHeights(const QuantizedMesh& mesh, TileKey k);
// The height the client draws at (u, v): the triangle's interpolation of `flattened`
// (flattenedHeights) plus sphereDrop at (u, v); NaN outside every triangle. O(triangles):
// for checks, not for drawing.
double drawnHeightAt(const QuantizedMesh& mesh, TileKey k, std::span<const double> flattened,
                     double u, double v);

struct TerrainTile {
    QuantizedMesh mesh;
    double error = 0.0; // metres, see above
};

// The tile of `grid` with its TIN within `max_error` metres (its border lines within
// `border_error` when given: buildTin's rule for neighbours with different budgets). Throws
// ridge::Error for an invalid key, lines that break the rules above, a grid of the wrong size
// or with a non-finite height, or a bound buildTin refuses.
TerrainTile makeTerrainTile(const TileHeights& grid, double max_error,
                            std::optional<double> border_error = std::nullopt);

} // namespace ridge::web
