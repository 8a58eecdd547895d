#include "ridge/web/terrain_tile.h"

#include "ridge/core/error.h"
#include "ridge/lod/ellipsoid.h"
#include "ridge/web/tin_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace ridge::web {

namespace {

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

[[noreturn]] void fail(const std::string& what)
{
    throw Error("terrain tile: " + what);
}

// Lines from `first` to `last` (0 and 32767, either way round), strictly monotone.
void checkLines(const std::vector<int32_t>& lines, int32_t first, int32_t last, const char* name)
{
    if (lines.size() < 2 || lines.size() > size_t(QuantizedMesh::kMaxCoordinate) + 1)
        fail(std::string(name) + " has " + std::to_string(lines.size()) +
             " lines: must have 2 to 32768");
    if (lines.front() != first || lines.back() != last)
        fail(std::string(name) + " must run from " + std::to_string(first) + " to " +
             std::to_string(last));
    for (size_t i = 1; i < lines.size(); ++i)
        if ((last > first) ? lines[i] <= lines[i - 1] : lines[i] >= lines[i - 1])
            fail(std::string(name) + "[" + std::to_string(i) + "] = " + std::to_string(lines[i]) +
                 " does not move on from " + std::to_string(lines[i - 1]));
}

} // namespace

std::vector<int32_t> uniformLines(int cells)
{
    if (cells < 1 || cells > QuantizedMesh::kMaxCoordinate)
        fail("cells " + std::to_string(cells) + " outside [1, 32767]");
    std::vector<int32_t> out(size_t(cells) + 1);
    for (int i = 0; i <= cells; ++i)
        out[size_t(i)] =
            int32_t(std::lround(double(i) * QuantizedMesh::kMaxCoordinate / double(cells)));
    return out;
}

TileHeights uniformTileHeights(TileKey key, int cells)
{
    TileHeights t{key, uniformLines(cells), uniformLines(cells), {}};
    std::reverse(t.v.begin(), t.v.end());
    return t;
}

double sphereDrop(TileKey k, double u, double v)
{
    constexpr double kRadius = 6371000.0; // the mean Earth radius
    constexpr double kMax = QuantizedMesh::kMaxCoordinate;
    constexpr double kRadians = std::numbers::pi / 180.0;
    const GeoRect r = GeographicTms::rect(k);
    const double lat = (r.south + (r.north - r.south) * v / kMax) * kRadians;
    // Metres a unit east (at the point's own latitude) and north.
    const double kx = kRadius * std::cos(lat) * (r.east - r.west) * kRadians / kMax;
    const double ky = kRadius * (r.north - r.south) * kRadians / kMax;
    const double dx = kx * (u - 0.5 * kMax), dy = ky * (v - 0.5 * kMax);
    return (dx * dx + dy * dy) / (2.0 * kRadius);
}

std::vector<double> flattenedHeights(const QuantizedMesh& mesh, TileKey k)
{
    std::vector<double> out(mesh.vertexCount());
    for (uint32_t i = 0; i < out.size(); ++i)
        out[i] = decodedHeight(mesh, i) - sphereDrop(k, mesh.u[i], mesh.v[i]);
    return out;
}

double drawnHeightAt(const QuantizedMesh& mesh, TileKey k, std::span<const double> flattened,
                     double u, double v)
{
    for (size_t t = 0; t + 2 < mesh.triangles.size(); t += 3)
        if (const double g = triangleValueAt(mesh, t, u, v, flattened); !std::isnan(g))
            return g + sphereDrop(k, u, v);
    return std::numeric_limits<double>::quiet_NaN();
}

TerrainTile makeTerrainTile(const TileHeights& grid, double max_error,
                            std::optional<double> border_error)
{
    if (!GeographicTms::valid(grid.key))
        fail("no geographic tile " + std::to_string(grid.key.z) + "/" + std::to_string(grid.key.x) +
             "/" + std::to_string(grid.key.y));
    constexpr int32_t kMax = QuantizedMesh::kMaxCoordinate;
    checkLines(grid.u, 0, kMax, "u");
    checkLines(grid.v, kMax, 0, "v");
    if (grid.heights.size() != grid.u.size() * grid.v.size())
        fail(std::to_string(grid.heights.size()) + " heights for " + std::to_string(grid.u.size()) +
             " × " + std::to_string(grid.v.size()) + " lines");

    // The mesh: the grid's TIN in the format's coordinates, y growing south as rows do
    // (validates heights and the bound).
    std::vector<int32_t> ys(grid.v.size());
    for (size_t r = 0; r < ys.size(); ++r)
        ys[r] = kMax - grid.v[r];
    // Meshed in g = h − q (see the header): the TIN follows the chords' sag too.
    std::vector<float> flattened(grid.heights.size());
    for (size_t r = 0; r < grid.v.size(); ++r)
        for (size_t c = 0; c < grid.u.size(); ++c) {
            const size_t i = r * grid.u.size() + c;
            flattened[i] = float(grid.heights[i] - sphereDrop(grid.key, grid.u[c], grid.v[r]));
        }
    Tin tin = buildTin(flattened, grid.u, ys, max_error, border_error);
    // The vertices' own heights, h.
    for (size_t i = 0; i < tin.heights.size(); ++i)
        tin.heights[i] = grid.heights[size_t(tin.rows[i]) * grid.u.size() + tin.columns[i]];
    const size_t n = tin.heights.size();

    // Quantized vertices, and where the client puts them on the ellipsoid.
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
    const GeoRect rect = GeographicTms::rect(grid.key);
    constexpr double kRadians = std::numbers::pi / 180.0;
    for (size_t i = 0; i < n; ++i) {
        m.u[i] = uint16_t(grid.u[tin.columns[i]]);
        m.v[i] = uint16_t(grid.v[tin.rows[i]]);
        m.height[i] =
            range > 0.0 ? uint16_t(std::lround((tin.heights[i] - hmin) / range * kMax)) : 0;
        heights[i] = tin.heights[i];
        const double lon = rect.west + (rect.east - rect.west) * m.u[i] / kMax;
        const double lat = rect.south + (rect.north - rect.south) * m.v[i] / kMax;
        const glm::dvec3 p = lod::geodeticToEcef(wgs84, lon * kRadians, lat * kRadians, heights[i]);
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
