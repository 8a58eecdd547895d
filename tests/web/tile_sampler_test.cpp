// Web tiles read from an archive: the right level, the archive's surface at the tile's
// samples, shared edges read alike, and tiles off the archive left alone. The Everest
// fixture: 301 × 203 samples of 3″ (about 92 m), 86.75–87.00° E, 27.83–28.00° N, WGS 84.
#include "ridge/web/tile_sampler.h"

#include "ridge/core/error.h"

#include "fixture_archives.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace ridge;
using namespace ridge::web;

TEST(TileSampler, TracesTheArchivesExtentAndFindsItsTiles)
{
    const test::ScratchDir dir;
    TileSampler sampler(test::buildEverestArchive(dir));
    const GeoRect e = sampler.extent();
    EXPECT_NEAR(e.west, 86.749583, 1e-6);
    EXPECT_NEAR(e.east, 86.749583 + 301 * 0.000833333, 1e-6);
    EXPECT_NEAR(e.north, 28.000417, 1e-6);
    EXPECT_NEAR(e.south, 28.000417 - 203 * 0.000833333, 1e-6);
    EXPECT_TRUE(sampler.overlaps(GeographicTms::tileAt(12, 86.925, 27.988)));
    EXPECT_FALSE(sampler.overlaps(GeographicTms::tileAt(12, 10.0, 45.0)));
    // A tile far off the archive still reads: the edge faded out to 0 m (its neighbours must
    // meet it).
    const std::optional<SampledTile> far =
        sampler.sample(GeographicTms::tileAt(12, 10.0, 45.0), 64);
    ASSERT_TRUE(far);
    EXPECT_EQ(far->off_raster, far->grid.heights.size());
    EXPECT_EQ(*std::max_element(far->grid.heights.begin(), far->grid.heights.end()), 0.f);
    // Just off the fixture's west edge the edge's height goes on, fading: 0.1° out (a third
    // of the fixture's width), about 60 % of it.
    const std::optional<SampledTile> near =
        sampler.sample(GeographicTms::tileAt(12, 86.65, 27.9), 64);
    ASSERT_TRUE(near);
    EXPECT_GT(*std::max_element(near->grid.heights.begin(), near->grid.heights.end()), 1000.f);
    // 64-cell tiles reach the fixture's 92 m at zoom 11 (153 m samples; zoom 12's are 76 m).
    EXPECT_EQ(sampler.maxZoom(64), 11);
    EXPECT_EQ(sampler.verticalReference(), "unknown") << "the fixture states no vertical datum";
}

TEST(TileSampler, ReadsTheLevelAsFineAsTheTileAndItsSurface)
{
    const test::ScratchDir dir;
    const std::string path = test::buildEverestArchive(dir);
    TileSampler sampler(path);
    HeightQuery finest(path);
    const int L = finest.finestLevel();
    int previous = -1;
    for (int z = 6; z <= 13; ++z) {
        const TileKey k = GeographicTms::tileAt(z, 86.925, 27.988);
        const int level = sampler.levelFor(k, 64);
        EXPECT_GE(level, previous) << "deeper zooms read finer levels";
        previous = level;
        if (z >= 12) {
            EXPECT_EQ(level, L) << "zoom " << z << " samples finer than the archive";
        }
    }
    const TileKey k = GeographicTms::tileAt(12, 86.925, 27.988);
    const std::optional<SampledTile> t = sampler.sample(k, 64);
    ASSERT_TRUE(t);
    EXPECT_EQ(t->level, L);
    EXPECT_EQ(t->off_raster, 0u) << "zoom 12's tile lies inside the fixture";
    // The fixture is a north-up lon/lat grid: the tile's lines are its own samples inside
    // the tile (0.0439° / 3″ = 52.7 of them a side: 52 or 53) plus the edges.
    const size_t columns = t->grid.u.size(), rows = t->grid.v.size();
    EXPECT_TRUE(columns == 52u + 2u || columns == 53u + 2u) << columns;
    EXPECT_TRUE(rows == 52u + 2u || rows == 53u + 2u) << rows;
    ASSERT_EQ(t->grid.heights.size(), columns * rows);
    // Every inner grid sample is one of the archive's samples, exactly (lossless).
    const GeoRect rect = GeographicTms::rect(k);
    for (size_t r = 1; r + 1 < rows; r += 7)
        for (size_t c = 1; c + 1 < columns; c += 7) {
            const glm::dvec2 ll(rect.west + (rect.east - rect.west) * t->grid.u[c] / 32767.0,
                                rect.south + (rect.north - rect.south) * t->grid.v[r] / 32767.0);
            const HeightSample s =
                finest.sample(ll, PointSpace::LonLat, -1, QueryResampling::Nearest);
            EXPECT_EQ(t->grid.heights[r * columns + c], float(s.height)) << c << ", " << r;
        }
    EXPECT_GT(*std::max_element(t->grid.heights.begin(), t->grid.heights.end()), 5000.f);
}

TEST(TileSampler, NeighboursReadTheirSharedEdgeAlike)
{
    const test::ScratchDir dir;
    TileSampler sampler(test::buildEverestArchive(dir, "progressive", 33, 4.0));
    const TileKey k = GeographicTms::tileAt(12, 86.90, 27.95);
    const std::optional<SampledTile> a = sampler.sample(k, 32);
    const std::optional<SampledTile> east = sampler.sample({k.z, k.x + 1, k.y}, 32);
    const std::optional<SampledTile> north = sampler.sample({k.z, k.x, k.y + 1}, 32);
    ASSERT_TRUE(a && east && north);
    EXPECT_GT(a->archive_error, 0.0) << "a lossy archive states its bound";
    // Same lines along the shared edges, and the same heights on them, bit for bit.
    ASSERT_EQ(a->grid.v, east->grid.v);
    ASSERT_EQ(a->grid.u, north->grid.u);
    const size_t columns = a->grid.u.size(), rows = a->grid.v.size();
    for (size_t r = 0; r < rows; ++r)
        EXPECT_EQ(a->grid.heights[r * columns + columns - 1],
                  east->grid.heights[r * east->grid.u.size()]);
    for (size_t c = 0; c < columns; ++c)
        EXPECT_EQ(a->grid.heights[c],
                  north->grid.heights[(north->grid.v.size() - 1) * columns + c]);
}

TEST(TileSampler, TilesPartlyOffTheArchiveCountTheirMissingSamples)
{
    const test::ScratchDir dir;
    TileSampler sampler(test::buildEverestArchive(dir));
    // Zoom 8's tile (0.70° square) holds the whole fixture and much besides.
    const std::optional<SampledTile> t =
        sampler.sample(GeographicTms::tileAt(8, 86.925, 27.988), 64);
    ASSERT_TRUE(t);
    EXPECT_GT(t->off_raster, 0u);
    EXPECT_LT(t->off_raster, t->grid.heights.size());
    EXPECT_THROW(sampler.sample({8, -1, 0}, 64), Error);
    EXPECT_THROW(sampler.sample(GeographicTms::tileAt(8, 86.9, 27.9), 0), Error);
    EXPECT_THROW(sampler.sample(GeographicTms::tileAt(8, 86.9, 27.9), 5000), Error);
}

TEST(TileSampler, AGlobalGridFrom0To360DegreesFillsBothHemispheres)
{
    // ETOPO5 at 2°, sample centres on 0, 2, ..., 360° E: the western hemisphere lies in the
    // grid's next period, which the tiles must still find.
    const test::ScratchDir dir;
    BuildOptions options;
    options.progress = {};
    const std::string path = dir.path("globe.ridge");
    buildArchive(test::dataPath("etopo5_globe_181x91.tif"), path, options);
    TileSampler sampler(path);
    for (const TileKey k :
         {TileKey{0, 0, 0}, TileKey{0, 1, 0}, TileKey{2, 1, 2}, TileKey{2, 6, 1}}) {
        const std::optional<SampledTile> t = sampler.sample(k, 32);
        ASSERT_TRUE(t) << k.z << "/" << k.x << "/" << k.y;
        EXPECT_LT(t->off_raster, t->grid.heights.size() / 2) << k.z << "/" << k.x << "/" << k.y;
        const auto [lo, hi] = std::minmax_element(t->grid.heights.begin(), t->grid.heights.end());
        EXPECT_GT(*hi - *lo, 1000.f) << "relief, not a fill: " << k.z << "/" << k.x << "/" << k.y;
    }
    // The seam: the western hemisphere's east edge is the grid's 360° column, the eastern
    // one's west edge its 0° column — the same samples, so the same heights.
    const std::optional<SampledTile> west = sampler.sample({1, 1, 0}, 32);
    const std::optional<SampledTile> east = sampler.sample({1, 2, 0}, 32);
    ASSERT_TRUE(west && east);
    ASSERT_EQ(west->grid.v, east->grid.v);
    const size_t wc = west->grid.u.size(), ec = east->grid.u.size();
    for (size_t r = 0; r < west->grid.v.size(); ++r)
        EXPECT_EQ(west->grid.heights[r * wc + wc - 1], east->grid.heights[r * ec]) << "row " << r;
}
