#pragma once
// PMTiles version 3 archives (github.com/protomaps/PMTiles, spec/v3): one file of tiles for
// static hosting, read with HTTP range requests.
//
// Layout written: the 127-byte header and the root directory inside the first 16 KiB (the
// spec's rule, so a client reads both with one request), then the tile data in tile-id order
// (clustered), then the metadata and the leaf directories. Identical consecutive tiles are
// one entry with a run length, and identical tiles anywhere are stored once (the contents
// count says how many distinct). Directories and metadata are gzip-compressed. Tile ids run
// along the Hilbert curve of each zoom (pmtilesTileId).
//
// Geographic (TMS, two root tiles) quantized-mesh tiles have no PMTiles tiling of their own:
// ridge stores geographic tile (z, x, y) as PMTiles tile (z + 1, x, y) — zoom z's 2^(z+1) × 2^z
// tiles fill the upper half of zoom z + 1's square — and says so in the metadata
// ("ridge:tiling": "geographic-tms+1").
#include "ridge/web/tile_grid.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ridge::web {

// Tile type byte of the header.
enum class PmtilesType : uint8_t { Unknown = 0, Mvt = 1, Png = 2, Jpeg = 3, Webp = 4, Avif = 5 };
// Compression byte (internal and tile).
enum class PmtilesCompression : uint8_t { Unknown = 0, None = 1, Gzip = 2, Brotli = 3, Zstd = 4 };

constexpr int kPmtilesMaxZoom = 26; // tile ids stay within 2^53 (JavaScript's integers)

// The tile id of (z, x, y) in PMTiles' XYZ scheme: tiles of lower zooms first, then the
// Hilbert index. Throws ridge::Error for z past kPmtilesMaxZoom or x, y outside the zoom.
uint64_t pmtilesTileId(TileKey k);
TileKey pmtilesTileKey(uint64_t id);

struct PmtilesHeader {
    PmtilesType tile_type = PmtilesType::Unknown;
    PmtilesCompression tile_compression = PmtilesCompression::None;
    int min_zoom = 0, max_zoom = 0;
    GeoRect bounds{-180, -85, 180, 85}; // degrees
    int center_zoom = 0;
    double center_lon = 0, center_lat = 0;
};

// Writes a PMTiles archive through a file descriptor the caller owns (an AtomicOutput's).
// Tiles must come in strictly increasing tile id. Not thread-safe.
class PmtilesWriter {
  public:
    PmtilesWriter(int fd, std::string path_for_messages);
    ~PmtilesWriter();
    PmtilesWriter(const PmtilesWriter&) = delete;
    PmtilesWriter& operator=(const PmtilesWriter&) = delete;

    // Throws ridge::Error for an id not above the last one's, an empty tile, or a failed
    // write (naming the path).
    void add(uint64_t tile_id, std::span<const uint8_t> bytes);
    // Writes the metadata (a JSON object), the directories and the header. Call once, last.
    void finish(const PmtilesHeader& header, const std::string& metadata_json);

    uint64_t tileCount() const { return addressed_; }
    uint64_t bytesWritten() const { return end_; }

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    uint64_t addressed_ = 0, end_ = 0;
};

// A PMTiles archive read back (for tests and checks): the header, the metadata, and any
// tile. Validates every header field, the directories' varints and offsets.
class PmtilesReader {
  public:
    // Throws ridge::Error naming `path` when it cannot be read or is not a valid archive.
    explicit PmtilesReader(const std::string& path);
    ~PmtilesReader();
    const PmtilesHeader& header() const;
    const std::string& metadata() const;
    uint64_t addressedTiles() const;
    uint64_t tileEntries() const;
    uint64_t tileContents() const;
    bool clustered() const;
    // The tile's bytes as stored, nullopt when absent.
    std::optional<std::vector<uint8_t>> tile(TileKey k) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace ridge::web
