// The tiles a Cesium client gets: within the error it assumes for their zoom, never claiming
// less than the archive's own bound.
#include "ridge/web/client_tile.h"

#include "fixture_archives.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace ridge;
using namespace ridge::web;

namespace {

// The largest |mesh − finest surface| over the archive's own finest samples inside the tile,
// found by the test alone (its own positions, meshHeightAt's brute-force search).
double errorAgainstFinestSamples(const ClientTile& t, TileKey k, HeightQuery& finest)
{
    const QuantizedMesh m = decodeQuantizedMesh(encodeQuantizedMesh(t.tile.mesh));
    const GeoRect r = GeographicTms::rect(k);
    const double step = 3.0 / 3600.0; // the fixture's spacing
    double worst = 0.0;
    for (int j = 0; j < 203; ++j)
        for (int i = 0; i < 301; ++i) {
            // The fixture's geotransform: origin (86.7495833…, 28.0004166…), 3″ pixels.
            const double lon = 86.749583333333334 + (i + 0.5) * step;
            const double lat = 28.000416666666666 - (j + 0.5) * step;
            if (lat > r.north || lat < r.south || lon < r.west || lon > r.east)
                continue;
            const HeightSample s = finest.sample({lon, lat}, PointSpace::LonLat);
            if (!s.on_raster)
                continue;
            const double u = (lon - r.west) / (r.east - r.west) * QuantizedMesh::kMaxCoordinate;
            const double v = (lat - r.south) / (r.north - r.south) * QuantizedMesh::kMaxCoordinate;
            worst = std::max(worst, std::abs(meshHeightAt(m, u, v) - s.height));
        }
    return worst;
}

} // namespace

TEST(ClientTile, KeepsToTheClientsErrorAtTheArchivesSamples)
{
    // A lossless archive: its level samples are the terrain. Zoom 11's tile reaches past the
    // fixture (its missing samples take the nearest valid height); 12 and 13 lie inside it.
    const test::ScratchDir dir;
    const std::string path = test::buildEverestArchive(dir);
    TileSampler sampler(path);
    HeightQuery finest(path);
    for (int z : {11, 12, 13}) {
        const TileKey k = GeographicTms::tileAt(z, 86.925, 27.988);
        const std::optional<ClientTile> t = makeClientTile(sampler, k, 64);
        ASSERT_TRUE(t);
        EXPECT_EQ(t->archive_error, 0.0) << "lossless";
        EXPECT_EQ(t->level, finest.finestLevel());
        // The test's own measurement, independent of the library's locator and sample list.
        const double measured = errorAgainstFinestSamples(*t, k, finest);
        std::printf("zoom %d: %zu vertices, client error %.2f m, TIN + step %.2f m, measured "
                    "%.2f m (test: %.2f m), claimed %.2f m\n",
                    z, t->tile.mesh.vertexCount(), t->client_error, t->tile.error,
                    t->measured_error, measured, t->claimed_error);
        EXPECT_NEAR(t->measured_error, measured, 1e-3) << "zoom " << z;
        EXPECT_GE(t->claimed_error, measured - 1e-3) << "zoom " << z;
        EXPECT_GE(t->claimed_error, t->tile.error);
        EXPECT_LE(t->tile.error, t->client_error) << "the TIN keeps to the client's budget";
        // On the archive's own samples (a north-up lon/lat archive) the mesh keeps to it at
        // the data too; a grid resampled at the tile's positions missed it by 2-5x here.
        EXPECT_LE(t->claimed_error, t->client_error) << "zoom " << z;
    }
}

TEST(ClientTile, NeverClaimsLessThanTheArchivesBound)
{
    const test::ScratchDir dir;
    TileSampler sampler(test::buildEverestArchive(dir, "progressive", 33, 4.0));
    // Zoom 15 assumes 2.35 m, less than the archive's 4 m: the tile keeps its samples and
    // claims the archive's bound.
    const std::optional<ClientTile> t =
        makeClientTile(sampler, GeographicTms::tileAt(15, 86.925, 27.988), 16);
    ASSERT_TRUE(t);
    EXPECT_NEAR(t->client_error, 2.352, 0.001);
    EXPECT_GT(t->archive_error, t->client_error);
    EXPECT_GE(t->claimed_error, t->archive_error);
    EXPECT_LE(t->tile.error,
              0.5 * (t->tile.mesh.max_height - t->tile.mesh.min_height) / 32767 + 1e-9)
        << "no TIN budget left: every sample kept";
}
