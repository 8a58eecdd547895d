// The tiles a Cesium client gets: within the error it assumes for their zoom, never claiming
// less than the archive's own bound.
#include "ridge/web/client_tile.h"

#include "everest_web.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace ridge;
using namespace ridge::web;

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
        const double measured = test::everestMeshError(
            decodeQuantizedMesh(encodeQuantizedMesh(t->tile.mesh)), k, finest);
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
