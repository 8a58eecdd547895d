#pragma once
// `ridge tiles`: an archive's web tiles written for static hosting — a directory of files or
// one PMTiles archive — made in parallel by a Tileset (the same tiles `ridge serve` answers),
// with progress, and atomically: the output appears complete or not at all.
//
// Directory: quantized-mesh as DIR/layer.json and DIR/Z/X/Y.terrain (gzip-compressed, as
// Cesium expects them served with Content-Encoding: gzip), every tile with the
// octvertexnormals, watermask and metadata extensions (a client ignores those it did not
// ask for); terrain-RGB as DIR/tiles.json (TileJSON) and DIR/Z/X/Y.png|webp. The directory is
// built under a temporary sibling name and renamed into place at the end.
// PMTiles (an output path ending in ".pmtiles"): pmtiles.h, the layer.json or TileJSON as its
// metadata.
#include "ridge/core/progress.h"
#include "ridge/web/tileset.h"

#include <optional>
#include <string>
#include <string_view>

namespace ridge::web {

enum class TileFormat { QuantizedMesh, MapboxRgb, TerrariumRgb };
const char* tileFormatName(TileFormat format); // "quantized-mesh", "terrain-rgb", "terrarium"
std::optional<TileFormat> parseTileFormat(std::string_view name);

struct TileWriteOptions {
    TileFormat format = TileFormat::QuantizedMesh;
    ImageFormat image = ImageFormat::Png; // terrain-RGB only
    int size = 256;                       // terrain-RGB pixels a side: 256 or 512
    int min_zoom = 0;
    int max_zoom = -1;      // -1: the deepest the archive supports (Tileset's)
    int threads = 0;        // tiles made at once; 0: the machine's cores
    TilesetOptions tileset; // cells, water (samplers follow threads)
    Progress progress;
    // Throws ridge::Error naming the field out of range.
    void validate() const;
};

struct TileWriteReport {
    int min_zoom = 0, max_zoom = 0;
    uint64_t tiles = 0;        // tiles written
    uint64_t bytes = 0;        // bytes of tiles written (as stored)
    uint64_t output_bytes = 0; // the whole output (PMTiles: the file)
    double seconds = 0.0;
    int threads = 0;
};

// Writes the tiles of `archive` to `output` (a directory that must not exist, or a .pmtiles
// file, replaced atomically). Throws ridge::Error naming the path or option at fault (an
// output that is the archive, a directory that exists, a zoom range outside the archive's),
// Cancelled when progress asks to stop; nothing is left at `output` then.
TileWriteReport writeTiles(const std::string& archive, const std::string& output,
                           const TileWriteOptions& options);

} // namespace ridge::web
