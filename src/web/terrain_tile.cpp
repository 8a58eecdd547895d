#include "ridge/web/terrain_tile.h"

#include "ridge/core/error.h"
#include "ridge/lod/ellipsoid.h"
#include "ridge/web/tin_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::web {

namespace {

// u or v of grid sample `index` of `cells`: exact at both ends, the same in every tile.
uint16_t quantizedCoordinate(int64_t index, int cells)
{
    return uint16_t(std::lround(double(index) * QuantizedMesh::kMaxCoordinate / cells));
}

// The vertices whose index satisfies `on`, sorted by `key` (the order along the edge).
template <class On, class Key> std::vector<uint32_t> edge(size_t count, On on, Key key)
{
    std::vector<uint32_t> out;
    for (uint32_t i = 0; i < count; ++i)
        if (on(i))
            out.push_back(i);
    std::sort(out.begin(), out.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    return out;
}

} // namespace

TerrainTile makeTerrainTile(const TileHeights& grid, double max_error)
{
    if (!GeographicTms::valid(grid.key))
        throw Error("terrain tile: no geographic tile " + std::to_string(grid.key.z) + "/" +
                    std::to_string(grid.key.x) + "/" + std::to_string(grid.key.y));
    if (grid.cells < 1 || grid.cells > 65535)
        throw Error("terrain tile: cells " + std::to_string(grid.cells) + " outside [1, 65535]");
    const int side = grid.cells + 1;
    if (grid.heights.size() != size_t(side) * size_t(side))
        throw Error("terrain tile: " + std::to_string(grid.heights.size()) + " heights for " +
                    std::to_string(side) + "² samples");

    // The mesh: the grid's TIN (validates heights and the bound).
    const Tin tin = buildTin(grid.heights, side, side, max_error);
    const size_t n = tin.heights.size();

    // Quantized vertices: u east from column 0, v north from the southern row.
    TerrainTile out;
    QuantizedMesh& m = out.mesh;
    const auto [lo, hi] = std::minmax_element(tin.heights.begin(), tin.heights.end());
    const double hmin = *lo, hmax = *hi, range = hmax - hmin;
    m.u.resize(n);
    m.v.resize(n);
    m.height.resize(n);
    std::vector<std::array<double, 3>> ecef(n);
    std::vector<double> heights(n);
    const lod::Ellipsoid wgs84 = lod::Ellipsoid::wgs84();
    constexpr double kRadians = std::numbers::pi / 180.0;
    for (size_t i = 0; i < n; ++i) {
        const int64_t c = tin.columns[i], j = grid.cells - int64_t(tin.rows[i]);
        m.u[i] = quantizedCoordinate(c, grid.cells);
        m.v[i] = quantizedCoordinate(j, grid.cells);
        m.height[i] = range > 0.0 ? uint16_t(std::lround((tin.heights[i] - hmin) / range *
                                                         QuantizedMesh::kMaxCoordinate))
                                  : 0;
        heights[i] = tin.heights[i];
        const glm::dvec3 p = lod::geodeticToEcef(
            wgs84, GeographicTms::longitude(grid.key, c, grid.cells) * kRadians,
            GeographicTms::latitude(grid.key, j, grid.cells) * kRadians, heights[i]);
        ecef[i] = {p.x, p.y, p.z};
    }
    // TIN triangles are counter-clockwise in (column, −row), which is (u, v).
    m.triangles = tin.triangles;
    // Edges in order along them (south to north, west to east).
    const auto by_v = [&](uint32_t i) { return m.v[i]; };
    const auto by_u = [&](uint32_t i) { return m.u[i]; };
    m.west = edge(
        n, [&](uint32_t i) { return m.u[i] == 0; }, by_v);
    m.east = edge(
        n, [&](uint32_t i) { return m.u[i] == QuantizedMesh::kMaxCoordinate; }, by_v);
    m.south = edge(
        n, [&](uint32_t i) { return m.v[i] == 0; }, by_u);
    m.north = edge(
        n, [&](uint32_t i) { return m.v[i] == QuantizedMesh::kMaxCoordinate; }, by_u);

    setBoundingVolumes(m, ecef, heights);
    // The header's range must be the one the heights were quantized over.
    m.min_height = float(hmin);
    m.max_height = float(hmax);
    orderForIndexCoding(m);
    out.error = tin.max_error + 0.5 * range / QuantizedMesh::kMaxCoordinate;
    return out;
}

} // namespace ridge::web
