// The web tilings: extents, shared edges, Cesium's geometric error and tile paths.
#include "ridge/web/tile_grid.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace ridge::web;

TEST(GeographicTms, ZoomZeroIsTwoHemispheresAndEachZoomHalvesTheTiles)
{
    const GeoRect west = GeographicTms::rect({0, 0, 0});
    const GeoRect east = GeographicTms::rect({0, 1, 0});
    EXPECT_EQ(west.west, -180.0);
    EXPECT_EQ(west.east, 0.0);
    EXPECT_EQ(east.east, 180.0);
    EXPECT_EQ(west.south, -90.0);
    EXPECT_EQ(west.north, 90.0);
    // TMS: y counts from the south.
    const GeoRect r = GeographicTms::rect({3, 9, 6});
    EXPECT_DOUBLE_EQ(r.west, -180.0 + 9 * 22.5);
    EXPECT_DOUBLE_EQ(r.south, -90.0 + 6 * 22.5);
    EXPECT_DOUBLE_EQ(r.east - r.west, 22.5);
    EXPECT_TRUE(GeographicTms::valid({3, 15, 7}));
    EXPECT_FALSE(GeographicTms::valid({3, 16, 7}));
    EXPECT_FALSE(GeographicTms::valid({3, 15, 8}));
    EXPECT_FALSE(GeographicTms::valid({3, -1, 0}));
    EXPECT_FALSE(GeographicTms::valid({kMaxTileZoom + 1, 0, 0}));
    EXPECT_FALSE(GeographicTms::valid({-1, 0, 0}));
}

TEST(GeographicTms, TileAtFindsTheTileHoldingAPoint)
{
    EXPECT_EQ(GeographicTms::tileAt(0, -90.0, 10.0), (TileKey{0, 0, 0}));
    EXPECT_EQ(GeographicTms::tileAt(0, 0.0, 10.0), (TileKey{0, 1, 0})) << "an edge: the east tile";
    EXPECT_EQ(GeographicTms::tileAt(0, 180.0, 90.0), (TileKey{0, 1, 0})) << "clamped";
    const TileKey k = GeographicTms::tileAt(12, 86.925, 27.988);
    const GeoRect r = GeographicTms::rect(k);
    EXPECT_TRUE(r.west <= 86.925 && 86.925 < r.east && r.south <= 27.988 && 27.988 < r.north);
}

TEST(GeographicTms, NeighboursComputeTheirSharedEdgeBitForBit)
{
    // A zoom where 64 cells a tile do not divide degrees exactly.
    for (int64_t x = 0; x + 1 < GeographicTms::tilesX(13); x += 997)
        for (int j = 0; j <= 64; ++j) {
            EXPECT_EQ(GeographicTms::longitude({13, x, 5}, 64, 64),
                      GeographicTms::longitude({13, x + 1, 5}, 0, 64));
            EXPECT_EQ(GeographicTms::latitude({13, x, 5}, 64, 64),
                      GeographicTms::latitude({13, x, 6}, 0, 64));
        }
}

TEST(GeographicTms, GeometricErrorIsCesiumsHeightmapEstimate)
{
    // 6378137 · 2π / 4 / (65 · 2) = 77,067.34 m, halved each zoom.
    EXPECT_NEAR(GeographicTms::geometricError(0), 77067.34, 0.01);
    EXPECT_NEAR(GeographicTms::geometricError(10), 77067.34 / 1024, 1e-4);
}

TEST(WebMercatorXyz, TilesSpanTheMercatorSquareFromTheNorth)
{
    const GeoRect world = WebMercatorXyz::rect({0, 0, 0});
    EXPECT_NEAR(world.north, 85.0511287798, 1e-9);
    EXPECT_NEAR(world.south, -85.0511287798, 1e-9);
    EXPECT_EQ(world.west, -180.0);
    const GeoRect nw = WebMercatorXyz::rect({1, 0, 0});
    EXPECT_NEAR(nw.south, 0.0, 1e-12) << "y counts from the north";
    EXPECT_NEAR(WebMercatorXyz::latitude({1, 0, 0}, 255.5, 256), 0.0, 1e-12);
    EXPECT_NEAR(WebMercatorXyz::longitude({1, 1, 0}, -0.5, 256), 0.0, 1e-12);
    EXPECT_NEAR(WebMercatorXyz::metresPerPixel(0, 0.0, 256), 156543.03, 0.01);
    EXPECT_FALSE(WebMercatorXyz::valid({2, 4, 0}));
    EXPECT_TRUE(WebMercatorXyz::valid({2, 3, 3}));
}

TEST(TilePath, ParsesZxyAndRefusesEverythingElse)
{
    const std::optional<TileKey> k = parseTilePath("12/3400/1200.terrain", ".terrain");
    ASSERT_TRUE(k);
    EXPECT_EQ(*k, (TileKey{12, 3400, 1200}));
    EXPECT_EQ(parseTilePath("0/0/0.png", ".png"), (TileKey{0, 0, 0}));
    for (const char* bad :
         {"12/3400/1200", "12/3400/1200.png", "-1/0/0.terrain", "1/+1/0.terrain", "1/01/0.terrain",
          "1//0.terrain", "1/0/0/0.terrain", "2147483648/0/0.terrain",
          "1/0/99999999999999999999.terrain", "1/0/0.terrain.terrain", " 1/0/0.terrain",
          "1/0/0 .terrain", "a/b/c.terrain", ".terrain", ""})
        EXPECT_FALSE(parseTilePath(bad, ".terrain")) << bad;
    // Well formed but outside the tiling: parsed, and not valid.
    const std::optional<TileKey> deep = parseTilePath("29/0/0.terrain", ".terrain");
    ASSERT_TRUE(deep);
    EXPECT_FALSE(GeographicTms::valid(*deep));
}
