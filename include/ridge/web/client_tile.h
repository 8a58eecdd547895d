#pragma once
// The quantized-mesh tile a Cesium client gets for a geographic tile: read from the archive
// (tile_sampler.h), meshed within the error the client assumes for the tile's zoom.
//
// The client refines a tile when its geometric error, GeographicTms::geometricError(z),
// projects past its screen-space threshold, so the tile must lie that close to the terrain.
// The error claimed is the sum of what stands between the mesh and the archive's finest
// samples at the tile's samples: the TIN's bound, half a height quantization step, and the
// archive's own bound at the level read (the largest Err(P) there). The TIN gets what the
// budget leaves after the other two, and never less than 0: where the archive's bound alone
// exceeds the client's error (a lossy archive at deep zooms), the tile keeps every sample and
// claims the archive's bound — never less.
//
// Between the tile's samples the mesh interpolates the tile's grid, not the terrain: the
// level's own samples there may lie farther from it (rough terrain whose detail is finer than
// the tile's grid, or a sample beside the archive's edge). So the mesh is also measured
// against every valid sample of the level read inside the tile (measured_error), and the claim
// is the larger of the two plus the archive's bound: a claim, not a hope. Where it exceeds the
// client's error (on steep ground, where rounding vertices to the format's 1/32767 grid moves
// the surface), the TIN is made again on a budget short by the excess (twice at most). The
// level read is levelWithin(half the client's error): finer than the tile's spacing needs
// where a coarse level's bound would not leave the TIN enough. Where the claim
// exceeds the client's error the client refines that tile later than it should (no crack;
// docs/PERF.md, "Web tiles", gives how often on real terrain).
#include "ridge/web/terrain_tile.h"
#include "ridge/web/tile_sampler.h"

#include <optional>

namespace ridge::web {

struct ClientTile {
    TerrainTile tile;          // tile.error: the TIN's bound + half a height step
    int level = 0;             // the archive level read
    double archive_error = 0.; // the largest Err(P) of the patches read, metres
    // The largest |mesh − level sample| over the level's valid samples inside the tile.
    double measured_error = 0.;
    double claimed_error = 0.;  // max(tile.error, measured_error) + archive_error, metres
    double client_error = 0.;   // GeographicTms::geometricError(z)
    size_t missing = 0;         // samples off the raster or on nodata (filled from the nearest)
    TileHeights grid;           // the grid the mesh was made from (tile_sampler.h)
    std::vector<uint8_t> flags; // per grid sample: SampledTile::kAbsent, kWater
};

// The tile `k` sampled with `cells` cells a side, or nullopt when it misses the archive.
// Throws ridge::Error as TileSampler::sample and makeTerrainTile do.
std::optional<ClientTile> makeClientTile(TileSampler& sampler, TileKey k, int cells = 64);

} // namespace ridge::web
