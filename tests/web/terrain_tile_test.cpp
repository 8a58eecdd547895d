// Quantized-mesh tiles from height grids: within their stated error through the format, and
// neighbours that meet on identical edge vertices.
#include "ridge/web/terrain_tile.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

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
        double worst = 0.0;
        for (int r = 0; r <= cells; ++r)
            for (int c = 0; c <= cells; ++c) {
                // u, v as the tile quantized them (the sample's own position on the mesh).
                const double u = std::round(c * 32767.0 / cells);
                const double v = std::round((cells - r) * 32767.0 / cells);
                const double h = meshHeightAt(m, u, v);
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
    for (size_t r = 0; r < t.v.size(); ++r)
        for (size_t c = 0; c < t.u.size(); ++c)
            EXPECT_LE(std::abs(meshHeightAt(m, t.u[c], t.v[r]) - t.heights[r * t.u.size() + c]),
                      tile.error + 1e-3);
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
