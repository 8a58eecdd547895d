#pragma once
// A quantized-mesh-1.0 tile of a geographic TMS tile made from the tile's height grid: the
// grid's error-bounded TIN (tin_mesh.h), quantized to the format's 15-bit coordinates, with
// its edge lists for the client's skirts, its bounding volumes on WGS 84 and the vertex order
// the index coding needs.
//
// Error: every grid sample lies within TerrainTile::error of the tile's decoded mesh — the
// TIN's bound plus half a height quantization step, (max − min) / 32767 / 2. (The grid's own
// distance from the terrain is the caller's to add: resampling, the archive's bound.)
//
// Shared edges: the TIN's border vertices depend on the border's samples alone, u and v are
// fixed functions of the sample index, so two tiles of a zoom that share an edge put vertices
// at the same samples with the same u or v there; their heights agree within each tile's half
// quantization step.
#include "ridge/web/quantized_mesh.h"
#include "ridge/web/tile_grid.h"

#include <string>
#include <vector>

namespace ridge::web {

struct TileHeights {
    TileKey key;   // GeographicTms
    int cells = 0; // the grid has cells + 1 samples a side, at GeographicTms::longitude/latitude
    // (cells + 1)² heights above the ellipsoid, metres, finite; row 0 the northern edge
    // (sample j = cells), column 0 the western.
    std::vector<float> heights;
};

struct TerrainTile {
    QuantizedMesh mesh;
    double error = 0.0; // metres, see above
};

// The tile of `grid` with its TIN within `max_error` metres. Throws ridge::Error for an
// invalid key, cells outside [1, 65535], a grid of the wrong size or with a non-finite
// height, or a max_error buildTin refuses.
TerrainTile makeTerrainTile(const TileHeights& grid, double max_error);

} // namespace ridge::web
