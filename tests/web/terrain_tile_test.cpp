// Quantized-mesh tiles from height grids: within their stated error through the format, and
// neighbours that meet on identical edge vertices.
#include "ridge/web/terrain_tile.h"

#include "ridge/lod/ellipsoid.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

using namespace ridge;
using namespace ridge::web;

namespace {

// Heights of a rough synthetic terrain at global sample (gx, gy) of zoom 10's 64-cell grid:
// neighbouring tiles read identical samples on their shared edges, as tiles cut from one
// archive do.
float terrain(int64_t gx, int64_t gy)
{
    const double x = double(gx) * 0.05, y = double(gy) * 0.05;
    return float(1500.0 + 600.0 * std::sin(x) * std::cos(0.7 * y) + 80.0 * std::sin(3.1 * x + y) +
                 15.0 * std::sin(17.0 * x) * std::sin(13.0 * y) +
                 double((gx * 7919 + gy * 104729) % 13) * 0.4);
}

TileHeights tileOf(TileKey k, int cells)
{
    TileHeights t = uniformTileHeights(k, cells);
    for (int r = 0; r <= cells; ++r)
        for (int c = 0; c <= cells; ++c)
            t.heights.push_back(terrain(k.x * cells + c, k.y * cells + (cells - r)));
    return t;
}

} // namespace

TEST(TerrainTile, EverySampleLiesWithinTheStatedErrorOfTheDecodedMesh)
{
    const int cells = 64;
    for (double bound : {0.5, 4.0, 20.0}) {
        const TileHeights grid = tileOf({10, 1500, 700}, cells);
        const TerrainTile tile = makeTerrainTile(grid, bound);
        EXPECT_LE(tile.error,
                  bound + 0.5 * (tile.mesh.max_height - tile.mesh.min_height) / 32767 + 1e-9);
        const QuantizedMesh m = decodeQuantizedMesh(encodeQuantizedMesh(tile.mesh));
        const std::vector<double> flattened = flattenedHeights(m, grid.key);
        double worst = 0.0;
        for (int r = 0; r <= cells; ++r)
            for (int c = 0; c <= cells; ++c) {
                // u, v as the tile quantized them (the sample's own position on the mesh).
                const double u = std::round(c * 32767.0 / cells);
                const double v = std::round((cells - r) * 32767.0 / cells);
                const double h = drawnHeightAt(m, grid.key, flattened, u, v);
                ASSERT_FALSE(std::isnan(h)) << "sample " << c << ", " << r << " outside the mesh";
                worst = std::max(worst,
                                 std::abs(h - double(grid.heights[size_t(r * (cells + 1) + c)])));
            }
        EXPECT_LE(worst, tile.error + 1e-3) << "bound " << bound; // float decode of the client
        EXPECT_LT(m.vertexCount(), size_t((cells + 1) * (cells + 1)));
    }
}

TEST(TerrainTile, NeighboursShareTheirEdgeVertices)
{
    const int cells = 64;
    const TerrainTile west = makeTerrainTile(tileOf({10, 1500, 700}, cells), 2.0);
    const TerrainTile east = makeTerrainTile(tileOf({10, 1501, 700}, cells), 2.0);
    const TerrainTile north = makeTerrainTile(tileOf({10, 1500, 701}, cells), 2.0);
    // v → metres along the shared meridian; u → metres along the shared parallel.
    auto along = [](const QuantizedMesh& m, const std::vector<uint32_t>& edge, bool by_v) {
        std::map<uint16_t, double> out;
        for (uint32_t i : edge)
            out[by_v ? m.v[i] : m.u[i]] = decodedHeight(m, i);
        return out;
    };
    const auto a = along(west.mesh, west.mesh.east, true);
    const auto b = along(east.mesh, east.mesh.west, true);
    ASSERT_EQ(a.size(), b.size());
    for (auto ia = a.begin(), ib = b.begin(); ia != a.end(); ++ia, ++ib) {
        EXPECT_EQ(ia->first, ib->first) << "same v on both sides of the seam";
        EXPECT_NEAR(ia->second, ib->second, west.error + east.error);
    }
    const auto c = along(west.mesh, west.mesh.north, false);
    const auto d = along(north.mesh, north.mesh.south, false);
    ASSERT_EQ(c.size(), d.size());
    for (auto ic = c.begin(), id = d.begin(); ic != c.end(); ++ic, ++id)
        EXPECT_EQ(ic->first, id->first) << "same u on both sides of the seam";
    // Every edge list is the tile's border vertices, in order along the edge.
    for (const auto* e : {&west.mesh.west, &west.mesh.east})
        for (size_t k = 1; k < e->size(); ++k)
            EXPECT_LT(west.mesh.v[(*e)[k - 1]], west.mesh.v[(*e)[k]]);
}

TEST(TerrainTile, ARectilinearGridKeepsItsSamplesWithinTheErrorToo)
{
    // Lines as a tile cut from an archive has them: edges, then samples 1000 apart but for
    // the first and last spacings.
    TileHeights t{{10, 1500, 700}, {0}, {32767}, {}};
    for (int32_t x = 700; x < 32767; x += 1000)
        t.u.push_back(x);
    t.u.push_back(32767);
    for (int32_t y = 450; y < 32767; y += 1000)
        t.v.push_back(32767 - y);
    t.v.push_back(0);
    for (size_t r = 0; r < t.v.size(); ++r)
        for (size_t c = 0; c < t.u.size(); ++c)
            t.heights.push_back(terrain(t.u[c] / 300, t.v[r] / 300));
    const TerrainTile tile = makeTerrainTile(t, 3.0);
    const QuantizedMesh m = decodeQuantizedMesh(encodeQuantizedMesh(tile.mesh));
    const std::vector<double> flattened = flattenedHeights(m, t.key);
    for (size_t r = 0; r < t.v.size(); ++r)
        for (size_t c = 0; c < t.u.size(); ++c)
            EXPECT_LE(std::abs(drawnHeightAt(m, t.key, flattened, t.u[c], t.v[r]) -
                               t.heights[r * t.u.size() + c]),
                      tile.error + 1e-3);
}

TEST(TerrainTile, FlatGroundFollowsTheGlobesCurvature)
{
    // Sea-level tiles at zooms 2 and 4 meshed within Cesium's error for them: the client
    // draws flat triangles in ECEF, so every sample's point on the ellipsoid must lie within
    // the bound of the chord triangle over it, measured here in 3-D by the test alone (the
    // triangle's corners in ECEF, barycentric in u, v, the distance along the up vector).
    // Without the curvature term the TIN keeps the 4 corners, whose chords pass 1,200 km
    // (zoom 2) under the surface.
    const lod::Ellipsoid wgs84 = lod::Ellipsoid::wgs84();
    constexpr double kRadians = std::numbers::pi / 180.0;
    for (const TileKey k : {TileKey{2, 5, 2}, TileKey{4, 20, 9}}) {
        const int cells = 64;
        TileHeights grid = uniformTileHeights(k, cells);
        grid.heights.assign(size_t((cells + 1) * (cells + 1)), 0.f);
        const double bound = GeographicTms::geometricError(k.z);
        const TerrainTile tile = makeTerrainTile(grid, bound);
        const QuantizedMesh& m = tile.mesh;
        EXPECT_GT(m.vertexCount(), 4u);
        const GeoRect r = GeographicTms::rect(k);
        const auto ecef = [&](double u, double v) {
            return lod::geodeticToEcef(wgs84, (r.west + (r.east - r.west) * u / 32767) * kRadians,
                                       (r.south + (r.north - r.south) * v / 32767) * kRadians, 0.0);
        };
        double worst = 0.0;
        for (size_t j = 0; j < grid.v.size(); ++j)
            for (size_t i = 0; i < grid.u.size(); ++i) {
                const double u = grid.u[i], v = grid.v[j];
                const glm::dvec3 p = ecef(u, v);
                for (size_t t = 0; t + 2 < m.triangles.size(); t += 3) {
                    const uint32_t a = m.triangles[t], b = m.triangles[t + 1],
                                   c = m.triangles[t + 2];
                    const double det = (double(m.u[b]) - m.u[a]) * (double(m.v[c]) - m.v[a]) -
                                       (double(m.u[c]) - m.u[a]) * (double(m.v[b]) - m.v[a]);
                    const double l1 = ((u - m.u[a]) * (double(m.v[c]) - m.v[a]) -
                                       (double(m.u[c]) - m.u[a]) * (v - m.v[a])) /
                                      det;
                    const double l2 = ((double(m.u[b]) - m.u[a]) * (v - m.v[a]) -
                                       (u - m.u[a]) * (double(m.v[b]) - m.v[a])) /
                                      det;
                    const double l0 = 1 - l1 - l2;
                    if (l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9)
                        continue;
                    const glm::dvec3 drawn = l0 * ecef(m.u[a], m.v[a]) + l1 * ecef(m.u[b], m.v[b]) +
                                             l2 * ecef(m.u[c], m.v[c]);
                    worst = std::max(worst, glm::length(p - drawn));
                    break;
                }
            }
        std::printf("zoom %d: %zu vertices, client error %.0f m, chords at most %.0f m from the "
                    "ellipsoid\n",
                    k.z, m.vertexCount(), bound, worst);
        // The paraboloid stands for the ellipsoid to first order in the tile's angle: the
        // chords lie 20 % past the tile's error at zoom 2 (45° tiles), 2 % at zoom 4 (11°).
        EXPECT_LE(worst, (k.z <= 2 ? 1.2 : 1.02) * tile.error) << "zoom " << k.z;
    }
}

TEST(TerrainTile, RefusesWhatIsNotATile)
{
    TileHeights g = tileOf({3, 1, 1}, 8);
    EXPECT_NO_THROW(makeTerrainTile(g, 1.0));
    TileHeights bad_key = g;
    bad_key.key = {3, 16, 0};
    EXPECT_THROW(makeTerrainTile(bad_key, 1.0), Error);
    TileHeights short_grid = g;
    short_grid.heights.pop_back();
    EXPECT_THROW(makeTerrainTile(short_grid, 1.0), Error);
    TileHeights nan = g;
    nan.heights[5] = NAN;
    EXPECT_THROW(makeTerrainTile(nan, 1.0), Error);
    EXPECT_THROW(makeTerrainTile(g, -1.0), Error);
    TileHeights unordered = g;
    std::swap(unordered.u[2], unordered.u[3]);
    EXPECT_THROW(makeTerrainTile(unordered, 1.0), Error) << "u must increase";
    TileHeights short_of_the_edge = g;
    short_of_the_edge.v.back() = 1;
    EXPECT_THROW(makeTerrainTile(short_of_the_edge, 1.0), Error) << "v must end on the south edge";
    EXPECT_THROW(uniformLines(0), Error);
    EXPECT_THROW(uniformLines(32768), Error);
}
